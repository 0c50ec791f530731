#include "apps/crex/distributed.h"

#include <algorithm>
#include <cstdlib>
#include <type_traits>

#ifdef CREX_WITH_MPI
#include <mpi.h>
#endif

namespace crex::app {

#ifdef CREX_WITH_MPI

namespace {

bool launched_by_mpirun() {
    // Open MPI sets these in every process it starts; a plain `crex run` has neither.
    return std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr || std::getenv("PMIX_RANK") != nullptr;
}

bool g_started = false;

}  // namespace

DistributedSession::DistributedSession(int& argc, char**& argv) {
    if (!launched_by_mpirun()) return;
    MPI_Init(&argc, &argv);
    g_started = true;
}

DistributedSession::~DistributedSession() {
    if (g_started) MPI_Finalize();
}

Distribution distribution() {
    Distribution d;
    if (!g_started) return d;
    MPI_Comm_rank(MPI_COMM_WORLD, &d.rank);
    MPI_Comm_size(MPI_COMM_WORLD, &d.size);
    return d;
}

void share_rows(const Distribution& d, Film& film, std::vector<double>& ambient) {
    if (!d.active()) return;
    const int width = film.width(), height = film.height();
    // Each buffer in place: rank r's band of rows goes to every rank (MPI_IN_PLACE: a rank's
    // own band is already where it belongs).
    auto gather = [&](void* data, size_t bytes_per_pixel) {
        std::vector<int> counts(static_cast<size_t>(d.size)), displs(static_cast<size_t>(d.size));
        for (int r = 0; r < d.size; ++r) {
            Distribution other{r, d.size};
            const size_t row_bytes = static_cast<size_t>(width) * bytes_per_pixel;
            counts[static_cast<size_t>(r)] = static_cast<int>(static_cast<size_t>(other.row_end(height) - other.row_begin(height)) * row_bytes);
            displs[static_cast<size_t>(r)] = static_cast<int>(static_cast<size_t>(other.row_begin(height)) * row_bytes);
        }
        MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, data, counts.data(), displs.data(), MPI_BYTE, MPI_COMM_WORLD);
    };
    film.for_each_buffer(gather);
    if (ambient.size() == 3 * film.pixel_count()) gather(ambient.data(), 3 * sizeof(double));
}

void share_cache_records(const Distribution& d, IrradianceCache& cache, size_t& shared) {
    if (!d.active()) return;
    static_assert(std::is_trivially_copyable_v<IrradianceRecord>);
    // The records this rank made since the last exchange are the cache's last ones: loaded
    // records came first, and others' are appended only here.
    const std::vector<IrradianceRecord>& all = cache.records();
    const size_t made = static_cast<size_t>(cache.stats().records);
    const size_t mine = std::min(made - std::min(shared, made), all.size());
    const int bytes = static_cast<int>(mine * sizeof(IrradianceRecord));
    std::vector<int> counts(static_cast<size_t>(d.size)), displs(static_cast<size_t>(d.size));
    MPI_Allgather(&bytes, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
    long long total = 0;
    for (int r = 0; r < d.size; ++r) displs[static_cast<size_t>(r)] = static_cast<int>(total), total += counts[static_cast<size_t>(r)];
    std::vector<IrradianceRecord> received(static_cast<size_t>(total) / sizeof(IrradianceRecord));
    std::vector<IrradianceRecord> own(all.end() - static_cast<std::ptrdiff_t>(mine), all.end());
    MPI_Allgatherv(own.data(), bytes, MPI_BYTE, received.data(), counts.data(), displs.data(), MPI_BYTE, MPI_COMM_WORLD);
    for (int r = 0; r < d.size; ++r) {
        if (r == d.rank) continue;
        const size_t first = static_cast<size_t>(displs[static_cast<size_t>(r)]) / sizeof(IrradianceRecord);
        const size_t n = static_cast<size_t>(counts[static_cast<size_t>(r)]) / sizeof(IrradianceRecord);
        for (size_t k = 0; k < n; ++k) cache.insert(received[first + k]);
    }
    shared = made;
}

namespace {
double reduce(double value, MPI_Op op) {
    if (!g_started) return value;
    double out = 0;
    MPI_Allreduce(&value, &out, 1, MPI_DOUBLE, op, MPI_COMM_WORLD);
    return out;
}
}  // namespace

double sum_over_ranks(double value) { return reduce(value, MPI_SUM); }
double max_over_ranks(double value) { return reduce(value, MPI_MAX); }

#else

DistributedSession::DistributedSession(int&, char**&) {}
DistributedSession::~DistributedSession() = default;
Distribution distribution() { return {}; }
void share_rows(const Distribution&, Film&, std::vector<double>&) {}
void share_cache_records(const Distribution&, IrradianceCache&, size_t&) {}
double sum_over_ranks(double value) { return value; }
double max_over_ranks(double value) { return value; }

#endif

}  // namespace crex::app

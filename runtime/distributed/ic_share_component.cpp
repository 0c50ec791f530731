#include "runtime/distributed/ic_share_component.h"

#include <chrono>
#include <set>

#ifdef CREX_WITH_MPI
#include <fmt/format.h>

#include <type_traits>

#include "runtime/distributed/rank_watchdog.h"
#include "runtime/distributed/record_exchange.h"
#endif

namespace crex::distributed {

ComponentRoles component_roles(int size, int rank) {
    ComponentRoles roles;
    roles.pa_count = std::max(1, size / 4);  // why one in four, not the thesis's half: the header
    roles.pr_count = size - roles.pa_count;
    roles.answers = rank >= roles.pr_count;
    if (roles.answers) {
        roles.pa_index = rank - roles.pr_count;
        for (int r = 0; r < roles.pr_count; ++r)
            if (r % roles.pa_count == roles.pa_index) roles.prs.push_back(r);
    } else {
        roles.pa = roles.pr_count + rank % roles.pa_count;
    }
    return roles;
}

#ifdef CREX_WITH_MPI

namespace {

// Tags of the protocol, on its own communicator: a PR's message is one of these, in order.
constexpr int kQueries = 1, kAtExchange = 2, kDone = 3, kAnswers = 4;

MPI_Comm g_protocol = MPI_COMM_NULL;  // all ranks
MPI_Comm g_pas = MPI_COMM_NULL;       // the PAs, for their record exchanges
MPI_Datatype g_query = MPI_DATATYPE_NULL;

static_assert(std::is_trivially_copyable_v<IcQuery>);
static_assert(sizeof(Vec3) == 3 * sizeof(double));

}  // namespace

void start_component_protocol(const ComponentRoles& roles) {
    MPI_Comm_dup(MPI_COMM_WORLD, &g_protocol);
    MPI_Comm_split(MPI_COMM_WORLD, roles.answers ? 0 : MPI_UNDEFINED, 0, &g_pas);
    // Queries by count, not bytes: a batch of more than 2^31 bytes (33 M queries) still goes.
    MPI_Type_contiguous(static_cast<int>(sizeof(IcQuery)), MPI_BYTE, &g_query);
    MPI_Type_commit(&g_query);
}

void IrradianceClient::answer(const std::vector<IcQuery>& queries, std::vector<Vec3>& irradiance) {
    irradiance.assign(queries.size(), Vec3{});
    if (queries.empty()) return;
    std::vector<MPI_Request> requests(2);
    MPI_Isend(queries.data(), static_cast<int>(queries.size()), g_query, pa_, kQueries, g_protocol, &requests[0]);
    MPI_Irecv(irradiance.data(), static_cast<int>(3 * queries.size()), MPI_DOUBLE, pa_, kAnswers, g_protocol, &requests[1]);
    wait_requests(requests, 2 * rank_timeout(), [&] { return fmt::format("rank {} did not answer irradiance queries", pa_); });
}

void IrradianceClient::at_exchange() {
    std::vector<MPI_Request> request(1);
    MPI_Isend(nullptr, 0, MPI_BYTE, pa_, kAtExchange, g_protocol, &request[0]);
    wait_requests(request, 2 * rank_timeout(), [&] { return fmt::format("rank {} did not take a message", pa_); });
}

void IrradianceClient::done() {
    std::vector<MPI_Request> request(1);
    MPI_Isend(nullptr, 0, MPI_BYTE, pa_, kDone, g_protocol, &request[0]);
    wait_requests(request, 2 * rank_timeout(), [&] { return fmt::format("rank {} did not take a message", pa_); });
}

ServeResult serve_irradiance(const ComponentRoles& roles, IrradianceCache& cache) {
    ServeResult out;
    // From the first message: the PRs' render time starts at their first camera ray, not at
    // this rank's start (their scene and cache set-up come before).
    std::chrono::steady_clock::time_point start;
    std::vector<int> live = roles.prs;
    std::set<int> at_exchange;
    size_t shared = 0;  // records this PA sent the other PAs
    int exchanges = 0;
    std::vector<IcQuery> queries;
    std::vector<Vec3> e;
    while (!live.empty()) {
        // One message from each PR in turn that is not in an exchange of rows.
        for (size_t k = 0; k < live.size(); ++k) {
            const int pr = live[k];
            if (at_exchange.count(pr)) continue;
            MPI_Status status;
            int flag = 0;
            wait_until([&] { return MPI_Iprobe(pr, MPI_ANY_TAG, g_protocol, &flag, &status), flag != 0; }, rank_timeout(),
                       [&] { return fmt::format("rank {} did not send irradiance queries or reach an exchange of rows", pr); });
            if (out.batches == 0 && status.MPI_TAG == kQueries) start = std::chrono::steady_clock::now();
            if (status.MPI_TAG == kQueries) {
                int n = 0;
                MPI_Get_count(&status, g_query, &n);
                queries.resize(static_cast<size_t>(n));
                MPI_Recv(queries.data(), n, g_query, pr, kQueries, g_protocol, MPI_STATUS_IGNORE);
                cache.irradiance(queries, 0, e);
                std::vector<MPI_Request> request(1);
                MPI_Isend(e.data(), 3 * n, MPI_DOUBLE, pr, kAnswers, g_protocol, &request[0]);
                wait_requests(request, rank_timeout(), [&] { return fmt::format("rank {} did not take its irradiance", pr); });
                ++out.batches, out.queries += static_cast<uint64_t>(n);
                stall_here_if_asked();
            } else {
                MPI_Recv(nullptr, 0, MPI_BYTE, pr, status.MPI_TAG, g_protocol, MPI_STATUS_IGNORE);
                if (status.MPI_TAG == kAtExchange) at_exchange.insert(pr);
                if (status.MPI_TAG == kDone) {
                    live.erase(live.begin() + static_cast<std::ptrdiff_t>(k));
                    --k;
                }
            }
        }
        if (!live.empty() && at_exchange.size() == live.size()) {
            // Every PR of this PA is in the exchange of rows (so is every other PA's): the PAs
            // exchange their records at the same point of the render.
            at_exchange.clear();
            allgather_new_records(g_pas, cache, shared,
                                  fmt::format("the PAs' exchange of irradiance records no. {} (--ic-share component)", ++exchanges));
        }
    }
    if (out.batches > 0) out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
}

#endif

}  // namespace crex::distributed

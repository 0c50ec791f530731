/// \file ic_share_component.h
/// --ic-share component (thesis 6.4, the component-based parallel irradiance cache): the
/// indirect diffuse work is split from the rest. PA ranks only answer irradiance-cache
/// queries; PR ranks render the rows (camera rays and every component) and hand each D step's
/// batch of queries (position, normal, the pixel's accuracy and priority, the random key of
/// the records it may make) to their PA, waiting for the irradiance. A PA answers with one
/// cache for all its PRs, so a record one PR's pixels made is there for every other PR's
/// next batch at once: no copies, no records made twice, and the D work is reordered by
/// batches, which the thesis found lowers the misses below one process's.
///
/// Roles: the highest max(1, floor(N/4)) ranks are PAs, the others PRs, so rank 0 renders and
/// writes; PR i is served by PA (i mod #PA). Rows are split over the PRs only. Not the thesis's
/// half: its PAs synchronised their caches every 8 records through the master, while PAs here
/// exchange records only where the PRs exchange rows (to stay deterministic), so each extra PA
/// splits the cache as --ic-share none does between those points (at N = 4, two PAs made as
/// many records as none on the Cornell box, one PA 35 % fewer). One in four keeps every
/// record in one cache up to N = 7.
///
/// Determinism: a PA serves its PRs in rank order, round-robin, one message each, blocking:
/// what it computes depends only on each PR's sequence of batches, which depends only on the
/// answers it got, so for a fixed N the image is the same on every run. (Serving whoever asks
/// first would idle less and depend on timing.) Before every exchange of rows a PR tells its
/// PA so, and the PA skips it until all its PRs are there (it would otherwise wait for a PR
/// that waits for the others in the exchange); with several PAs, that is when they exchange
/// the records each made (record_exchange.h), in rank order. With one PA (N = 2, 3) every
/// record is in one cache; with more, a PA sees the others' records from the next exchange of
/// rows on, so the image depends on N.
#pragma once

#ifdef CREX_WITH_MPI
#include <mpi.h>
#endif

#include <vector>

#include "runtime/cache/irradiance_cache.h"

namespace crex::distributed {

struct ComponentRoles {
    int pa_count = 0, pr_count = 0;
    bool answers = false;  ///< this rank is a PA
    int pa = -1;           ///< a PR's PA (world rank)
    std::vector<int> prs;  ///< a PA's PRs (world ranks), in rank order
    int pa_index = -1;     ///< a PA's index among the PAs (0: the one that sends rank 0 the records for --ic-file)
};

/// The roles of `size` ranks, as above (size >= 2).
ComponentRoles component_roles(int size, int rank);

#ifdef CREX_WITH_MPI

/// The communicators of the protocol (collective over all ranks; call once, after the roles).
void start_component_protocol(const ComponentRoles& roles);

/// A PR's side: its D batches go to its PA.
class IrradianceClient {
public:
    explicit IrradianceClient(int pa) : pa_(pa) {}
    /// E at `queries`, computed by the PA (bounded wait: twice --rank-timeout, since the PA may
    /// itself be waiting that long for another PR).
    void answer(const std::vector<IcQuery>& queries, std::vector<Vec3>& irradiance);
    /// This rank is entering an exchange of rows: its PA serves the other PRs meanwhile.
    void at_exchange();
    /// No more queries from this rank.
    void done();

private:
    int pa_;
};

struct ServeResult {
    double seconds = 0;  ///< from the first message to the last PR's done
    uint64_t batches = 0, queries = 0;
};

/// A PA's side: answers its PRs' batches with `cache` until every PR said done.
ServeResult serve_irradiance(const ComponentRoles& roles, IrradianceCache& cache);

#endif

}  // namespace crex::distributed

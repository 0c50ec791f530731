/// \file mpi_group.h
/// The ProcessGroup of a run under mpirun (distributed.h): which rows this rank renders, how
/// the irradiance cache is shared (IcShare), the PA ranks' serve loop of the component-based
/// cache, the images at the exchanges of rows for a report, the totals over the ranks in rank
/// 0's notes, and every rank ended when one fails.
#pragma once

#include <memory>
#include <vector>

#include "runtime/distributed/distributed.h"
#include "runtime/distributed/mpi_comm.h"

namespace crex::distributed {

class MpiGroup final : public ProcessGroup {
public:
    explicit MpiGroup(const DistributedOptions& options);
    ~MpiGroup() override;

    int bands() const override { return ranks_.bands; }
    int band() const override { return ranks_.band; }
    void share_rows(SharedRows& rows) override;
    void sum(std::vector<double>& values) override;
    void share_cache(IrradianceCache& cache) override;
    void answer_queries(IrradianceCache& cache, const std::vector<IcQuery>& queries, std::vector<Vec3>& irradiance) override;
    bool saves_cache_file() const override { return ranks_.rank == 0; }
    void final_image(const std::vector<float>& rgb, int width) override;

    bool distributed() const override { return ranks_.active(); }
    bool leads() const override { return ranks_.rank == 0; }
    std::string share_from_lead(std::string bytes, const std::string& what) override;
    int processes() const override { return ranks_.size; }
    int process_index() const override { return ranks_.rank; }
    void tell_lead(const std::string& bytes, const std::string& what) override {
        (void)what;
        post_bytes(0, bytes, kFrameTag);
    }
    void told_lead(const std::string& what) override { wait_for_posted(what); }
    std::vector<std::string> all_share(const std::string& bytes, const std::string& what) override { return all_gather_bytes(bytes, what); }
    std::optional<std::string> heard_by_lead(bool wait, const std::string& what) override {
        return receive_bytes_from_any(kFrameTag, wait, what);
    }
    void keep_partial_outputs(const std::vector<std::string>& outputs, int width, int height, const ImageMetadata& identity) override;
    void begin(const PipelinePlan& plan, RunSettings& settings, const CheckpointRecorder* exchanges_for) override;
    /// A PA rank of IcShare::kComponent: it answers irradiance queries instead of rendering.
    bool serves_only() const override;
    /// A PA rank's whole run: serve until every PR is done, send rank 0 the records for the
    /// cache file (the first PA: it holds them), then the totals.
    void serve(const PipelinePlan& plan, const Scene& scene, const RunSettings& settings) override;
    /// The totals over all ranks; rank 0 gets them as notes (and saves the cache file under
    /// component, from the first PA).
    void end(const RunSettings& settings, RunResult& result) override;
    bool snapshots_mid_render() const override { return false; }
    std::vector<Checkpoint> exchange_checkpoints(const RunResult& result) const override;
    [[noreturn]] void fail(ProcessFailure why, const std::string& what) override;

private:
    struct Modes;
    DistributedOptions options_;
    Distribution ranks_;
    std::unique_ptr<Modes> modes_;
    double rays_ = 0, slowest_ = 0;
    double waited_before_ = 0;  // seconds waited for other ranks before the render
};

}  // namespace crex::distributed

#include "runtime/api/run.h"

#include "base/check.h"
#include "runtime/api/run_summary.h"

namespace crex {
namespace {

// Passes progress and a stop on; checkpoints only where a snapshot shows the image (not where other
// processes' rows arrive only at exchanges).
class Forward final : public RunObserver {
public:
    Forward(RunObserver& inner, bool snapshots) : inner_(inner), snapshots_(snapshots) {}
    void progress(const RunProgress& p) override { inner_.progress(p); }
    CheckpointRecorder* checkpoints() override { return snapshots_ ? inner_.checkpoints() : nullptr; }
    bool stop_requested() override { return inner_.stop_requested(); }

private:
    RunObserver& inner_;
    bool snapshots_;
};

}  // namespace

RunOutcome run_plan(const PipelinePlan& plan, const Scene& scene, const RunOptions& options, ProcessGroup& group,
                    RunObserver& observer) {
    return run_resolved(plan, scene, resolve_run(plan, options), group, observer);
}

RunOutcome run_resolved(const PipelinePlan& plan, const Scene& scene, ResolvedRun run, ProcessGroup& group, RunObserver& observer) {
    RunOutcome out{std::move(run), {}, std::nullopt};
    RunSettings& s = out.run.settings;
    CheckpointRecorder* recorder = observer.checkpoints();
    group.begin(plan, s, recorder);
    if (group.serves_only()) {
        try {
            group.serve(plan, scene, s);
        } catch (const std::exception& e) {  // the others would wait for their answers: end them
            group.fail(ProcessFailure::kServe, e.what());
            throw;
        }
        return out;
    }
    if (out.run.predicted) out.measured = out.run.predicted->profile;
    s.executor.profile = &out.measured;  // the budget predicts from it, the render measures into it
    Forward forward(observer, group.snapshots_mid_render());
    try {
        out.result.emplace(run_plan(scene, plan, s, group, forward));
    } catch (const InternalError& e) {
        group.fail(ProcessFailure::kInternal, e.what());
        throw;  // a bug, not a failed render: the caller says so
    } catch (const RunInputError& e) {
        group.fail(ProcessFailure::kInput, e.what());
        throw;
    } catch (const RunCancelled&) {
        throw;
    } catch (const std::exception& e) {
        group.fail(ProcessFailure::kRender, e.what());
        throw;
    }
    s.executor.profile = nullptr;
    for (Diagnostic& w : light_left_out_warnings(*out.result, s.executor.shade, s.irradiance_cache ? &*s.irradiance_cache : nullptr,
                                                  out.run.limits_set_at))
        out.result->warnings.push_back(std::move(w));
    group.end(s, *out.result);
    if (recorder && !group.snapshots_mid_render())
        for (Checkpoint& c : group.exchange_checkpoints(*out.result)) recorder->add(std::move(c));
    return out;
}

std::vector<PolicyRun> render_other_policies(const PipelinePlan& plan, const Scene& scene, const ResolvedRun& run,
                                             pipeline::SchedulingPolicy used, double interval, const CheckpointScorer& scorer,
                                             const std::function<void(std::string_view)>& starting) {
    std::vector<PolicyRun> others;
    for (std::string_view name : pipeline::scheduling_policy_names()) {
        if (name == pipeline::name_of(used)) continue;
        if (starting) starting(name);
        RunSettings s = run.settings;
        s.policy = pipeline::scheduling_policy_from_name(name);
        Profile profile = run.predicted ? run.predicted->profile : Profile{};
        s.executor.profile = &profile;
        s.ic_file.clear();
        s.ic_file_bytes.reset();
        struct Recorder final : RunObserver {
            Recorder(double interval, const CheckpointScorer& scorer) : checkpoints_(interval, scorer) {}
            CheckpointRecorder* checkpoints() override { return &checkpoints_; }
            CheckpointRecorder checkpoints_;
        } recorder(interval, scorer);
        LocalGroup one;
        run_plan(scene, plan, s, one, recorder);
        others.push_back({std::string(name), recorder.checkpoints_.checkpoints()});
    }
    return others;
}

}  // namespace crex

/// \file process_group.h
/// The processes that render one image together (distributed rendering, thesis chapter 6), as
/// the render driver and the run API see them. One process is a LocalGroup: every method below
/// does nothing, or answers from here. Under mpirun it is an MpiGroup
/// (runtime/distributed/mpi_group.h): each process renders a band of rows, and the driver calls
/// share_rows() where every process must see the whole image (after the preview, before each
/// round's guidance, when the bands change, at the end). Tests use an in-process group of
/// threads (tests/support/thread_group.h). The driver declares here what it needs, so the
/// implementations depend on the driver, never the other way round.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "compiler/plan/pipeline_plan.h"
#include "runtime/cache/irradiance_cache.h"
#include "runtime/io/image_io.h"
#include "runtime/render/film.h"
#include "runtime/report/checkpoints.h"

namespace crex {

struct RunSettings;
struct RunResult;
struct Scene;

/// Why the processes exchange rows.
enum class RowExchange {
    kPreview,   ///< after the preview: guidance sees the whole image
    kNewBands,  ///< before round 1's bands replace the preview's, which held the work on the preview's samples
    kRound,     ///< before a later round's guidance
    kEnd,       ///< at the end: every row is final (what is written should the run fail)
};

/// What an exchange of rows shares: every per-pixel buffer of the render, each row as the
/// process whose band held it left it.
struct SharedRows {
    Film& film;
    std::vector<double>& ambient;  ///< the stand-ins the composite adds (per pixel RGB)
    /// --ambient auto: per component, the throughput of its rays left unexecuted (per pixel
    /// RGB), whose stand-ins are added at the end.
    std::vector<std::vector<float>*> throughput_left;
    const std::vector<int>& bounds;  ///< the split of the work since the last exchange (row_bands.h)
    RowExchange why;
};

/// Why a process fails, for the message a distributed group prints before ending every process.
enum class ProcessFailure {
    kInternal,  ///< a bug (InternalError)
    kInput,     ///< input the run cannot use (RunInputError)
    kRender,    ///< the render failed (I/O, Embree)
    kServe,     ///< answering the others' irradiance queries failed
};

class ProcessGroup {
public:
    virtual ~ProcessGroup() = default;

    // --- What the render driver asks (runtime/driver/run_plan.h). ---

    /// How many processes render rows (0: this one renders every row), and this one's band:
    /// band `band()` of each stage's split (row_bands.h), equal bands for the first stage, then
    /// bands of about the same camera samples, which every process chooses alike.
    virtual int bands() const { return 0; }
    virtual int band() const { return 0; }
    /// Every process's buffers take each band of rows from the process whose band held it.
    /// Collective over the processes that render rows.
    virtual void share_rows(SharedRows& rows) { (void)rows; }
    /// `values` summed over the processes that render rows, on each (all call it at the same
    /// point): --ambient auto's stand-ins from every process's rays.
    virtual void sum(std::vector<double>& values) { (void)values; }
    /// With a cache, where rows are shared mid-render: the processes exchange their records.
    virtual void share_cache(IrradianceCache& cache) { (void)cache; }
    /// With a cache: a batch of D queries answered, by `cache` here or by another process.
    virtual void answer_queries(IrradianceCache& cache, const std::vector<IcQuery>& queries, std::vector<Vec3>& irradiance) {
        cache.irradiance(queries, 0, irradiance);
    }
    /// Whether this process saves the cache file (one does).
    virtual bool saves_cache_file() const { return true; }
    /// The final image (RunResult::image(), `width` pixels a row) right after the last
    /// share_rows, every row final: what is written should the run fail from there on.
    virtual void final_image(const std::vector<float>& rgb, int width) { (void)rgb, (void)width; }

    // --- What the run API asks (runtime/api/run.h, runtime/api/shared_inputs.h). ---

    /// More than one process.
    virtual bool distributed() const { return false; }
    /// This process reads the inputs, writes the outputs and says what happened (rank 0).
    virtual bool leads() const { return true; }
    /// The lead's `bytes` on every process (the lead gets its own back). Collective; `what`
    /// names them should a process wait too long.
    virtual std::string share_from_lead(std::string bytes, const std::string& what) {
        (void)what;
        return bytes;
    }
    /// How many processes there are, and this one's place among them (0 for the lead): a
    /// sequence's frames are split among them (frame_sequence.h), each frame rendered whole
    /// by one process.
    virtual int processes() const { return 1; }
    virtual int process_index() const { return 0; }
    /// Every process's `bytes`, in process order, on every process (collective; bounded):
    /// the records each frame made, so that every process's cache holds every process's.
    virtual std::vector<std::string> all_share(const std::string& bytes, const std::string& what) {
        (void)what;
        return {bytes};
    }
    /// A process other than the lead tells it `bytes` (what one of its frames did), without
    /// waiting for the lead to take them (it may be in a collective this process joins next);
    /// told_lead() waits until the lead has taken all (bounded).
    virtual void tell_lead(const std::string& bytes, const std::string& what) { (void)bytes, (void)what; }
    virtual void told_lead(const std::string& what) { (void)what; }
    /// On the lead: the next `bytes` another process told it, if one has arrived; with `wait`,
    /// waits for one (bounded: a process silent past the timeout ends the run, named).
    virtual std::optional<std::string> heard_by_lead(bool wait, const std::string& what) {
        (void)wait, (void)what;
        return std::nullopt;
    }
    /// Where the rows this process finished are written should the group fail before the
    /// outputs (each of `outputs` as NAME.partial.EXT), with `identity` in their header.
    virtual void keep_partial_outputs(const std::vector<std::string>& outputs, int width, int height, const ImageMetadata& identity) {
        (void)outputs, (void)width, (void)height, (void)identity;
    }
    /// Before the render: this process's part in it (its rows, how the cache is shared) for
    /// `plan` with `settings`, which it may adjust; `exchanges_for`: the recorder the checkpoints
    /// of each exchange of rows go to (exchange_checkpoints()), null for none; their images are
    /// kept only where it scores them. Collective.
    virtual void begin(const PipelinePlan& plan, RunSettings& settings, const CheckpointRecorder* exchanges_for) {
        (void)plan, (void)settings, (void)exchanges_for;
    }
    /// A process that renders no rows (it answers the others' irradiance queries) does its
    /// whole part in serve() instead of rendering.
    virtual bool serves_only() const { return false; }
    virtual void serve(const PipelinePlan& plan, const Scene& scene, const RunSettings& settings) {
        (void)plan, (void)scene, (void)settings;
    }
    /// After this process's render: totals over every process, said as notes on `result` by
    /// the lead. Collective.
    virtual void end(const RunSettings& settings, RunResult& result) { (void)settings, (void)result; }
    /// Whether image snapshots during the render show the image: not where the other processes'
    /// rows arrive only at exchanges. Then exchange_checkpoints() stands in for them.
    virtual bool snapshots_mid_render() const { return true; }
    /// After end(), on the lead: the image after each exchange of rows and at the end (the
    /// rays and the slowest process's time over every process).
    virtual std::vector<Checkpoint> exchange_checkpoints(const RunResult& result) const {
        (void)result;
        return {};
    }
    /// A failure on this process: a distributed group ends every process (the others would wait
    /// for this one) after saying `what`, and does not return; one process returns, and the
    /// caller reports the failure as usual.
    virtual void fail(ProcessFailure why, const std::string& what) { (void)why, (void)what; }
};

/// One process: every row rendered here, nothing shared.
class LocalGroup final : public ProcessGroup {};

}  // namespace crex

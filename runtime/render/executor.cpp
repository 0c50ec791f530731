#include "runtime/render/executor.h"

#include <fmt/format.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "base/render_text.h"
#include "compiler/sched/print.h"
#include "runtime/base/sampling.h"

namespace crex {

Executor::Executor(const RenderScene& scene, Film& film, const ExecutorOptions& options)
    : scene_(scene), film_(film), options_(options) {}

double Executor::importance(uint32_t pixel) const {
    double v = options_.importance ? static_cast<double>((*options_.importance)[pixel]) : options_.constant_importance;
    if (std::isnan(v)) return 0;
    return std::fmin(std::fmax(v, 0.0), 1.0);
}

namespace {
// Scales c down so that its largest channel is at most `limit`, keeping its hue.
Vec3 clamped(const Vec3& c, double limit) {
    double m = std::max({c.x, c.y, c.z});
    return m > limit ? c * (limit / m) : c;
}
}  // namespace

std::optional<double> Executor::admission_cost(Component c) const {
    if (!options_.profile) return std::nullopt;
    const std::optional<double> profiled = options_.profile->cost(c), recent = recent_.cost(c);
    if (!profiled || !recent) return profiled ? profiled : recent;
    return std::max(*profiled, *recent);
}

double Executor::now() const {
    if (options_.clock) return options_.clock();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

size_t Executor::chunk_rays() const {
    if (options_.chunk_rays > 0) return options_.chunk_rays;
    return 4096 * static_cast<size_t>(std::max(1, tbb::this_task_arena::max_concurrency()));
}

size_t Executor::execute_rays(const RayBatch& rays, bool camera, size_t aov, ComponentStats& stats, const std::string& label,
                              std::optional<Component> profiled, bool paced) {
    double start = now();
    auto& sink = deferring_ ? pending_ : bins_;
    const bool queries = options_.irradiance && !camera && !rays.empty() && (rays.flags[0] & kRayIcQuery);
    // Paced (under a budget, by a caller that keeps what is not run): cache queries are handed
    // over in parts that start small and double, each at most half the time left at the cost
    // per query of the part before, and the rest is left when the budget is spent. A query's
    // cost is that of the records it makes, which no profile predicts: on the room (prog_tc,
    // 384x288, 0.5 s) one batch of 2,773 queries admitted at 27 us each took 145 ms.
    paced = paced && queries && budget_active();
    size_t chunk = queries ? (paced ? kFirstPacedQueries : std::max<size_t>(options_.query_chunk_rays, 1)) : chunk_rays();
    running_ = &rays;
    struct NotRunning {
        const RayBatch*& running;
        ~NotRunning() { running = nullptr; }
    } not_running{running_};
    size_t begin = 0;
    for (double per_query = 0; begin < rays.size(); begin += chunk) {
        if (paced && begin > 0) {
            const double remaining = options_.budget_seconds - now();
            const double fits = per_query > 0 ? 0.5 * remaining / per_query : 2.0 * static_cast<double>(chunk);
            if (!(fits >= 1)) break;
            chunk = std::min({2 * chunk, static_cast<size_t>(std::min(fits, 1e9)), std::max<size_t>(options_.query_chunk_rays, 1)});
        }
        const double chunk_start = now();
        size_t end = std::min(rays.size(), begin + chunk);
        running_next_ = end;
        for (size_t i = begin; i < end; ++i) stats.beta[0] += rays.br[i], stats.beta[1] += rays.bg[i], stats.beta[2] += rays.bb[i];
        if (queries) {  // cached D: interpolate
            std::vector<Vec3> e;
            pacing_queries_ = paced;  // the cache may stop making records once the budget is spent
            options_.irradiance(rays, begin, end, e);
            pacing_queries_ = false;
            if (e.size() != end - begin) {  // stopped: these queries are left, like the rest
                if (paced) break;
                e.resize(end - begin);
            }
            for (size_t i = begin; i < end; ++i) {
                Vec3 beta{rays.br[i], rays.bg[i], rays.bb[i]};
                Vec3 c = beta * e[i - begin] / kPi;
                if (options_.clamp_indirect > 0) c = clamped(c, options_.clamp_indirect);
                stats.luminance += is_finite(c) ? luminance(c) : 0.0;
                film_.add(aov, rays.pixel[i], is_finite(c) ? c : Vec3{}, rays.flags[i]);
                film_.count_ray(aov, rays.pixel[i]);
            }
            stats.rays += end - begin;
            rays_done_ += end - begin;
            if (options_.progress) options_.progress(label, rays_done_);
            if (options_.checkpoint) options_.checkpoint(label, false);
            per_query = (now() - chunk_start) / static_cast<double>(end - begin);
            continue;
        }
        ShadeOutput& out = shade_;
        trace_and_shade(scene_, rays, begin, end, camera, options_.shade, out);
        if (!camera && options_.clamp_indirect > 0)
            for (Vec3& c : out.contribution) c = clamped(c, options_.clamp_indirect);
        if (!camera)
            for (const Vec3& c : out.contribution) stats.luminance += is_finite(c) ? luminance(c) : 0.0;
        if (!(camera && options_.replay_branches))
            film_.add_rays(aov, rays.pixel.data() + begin, rays.flags.data() + begin, out.contribution.data(),
                           camera ? out.emission.data() : nullptr, out.contribution.size());
        if (camera && film_.tracked_branches()) gate_first_bounce(out);
        out.append_children_to(sink);
        stats.rays += end - begin;
        stats.shadow_rays += out.shadow_rays;
        stats_.cut_by_depth += out.cut_by_depth;
        stats_.cut_by_weight += out.cut_by_weight;
        rays_done_ += end - begin;
        if (options_.progress) options_.progress(label, rays_done_);
        if (options_.checkpoint) options_.checkpoint(label, false);
    }
    const size_t executed = std::min(begin, rays.size());
    double seconds = now() - start;
    stats.seconds += seconds;
    if (options_.profile) {
        if (profiled) options_.profile->record(*profiled, executed, seconds), recent_.record(*profiled, executed, seconds);
        else if (camera) options_.profile->record_camera(executed, seconds);
    }
    return executed;
}

void Executor::gate_first_bounce(ShadeOutput& out) {
    const uint8_t tracked = film_.tracked_branches(), replay = options_.replay_branches;
    const std::vector<uint8_t>* runs = options_.first_bounce_runs;
    for (size_t b = 0; b < out.blocks; ++b)
        for (size_t c = 0; c < kComponentCount; ++c) {
            RayBatch& rays = out.block_children[b][c];
            if (replay && !(replay >> c & 1u)) {  // a replay runs its components' branches only
                rays.reset();
                continue;
            }
            if (!(tracked >> c & 1u)) continue;
            size_t kept = 0;
            for (size_t i = 0; i < rays.size(); ++i) {
                const uint32_t p = rays.pixel[i];
                const bool run = !runs || ((*runs)[p] >> c & 1u);
                film_.add_first_bounce(c, p, {rays.br[i], rays.bg[i], rays.bb[i]}, run, replay != 0, rays.flags[i] & kRayOddSample);
                if (!run) continue;
                if (kept != i) {
                    const RayRecord r = rays.get(i);
                    rays.write(kept, &r, 1);
                }
                ++kept;
            }
            rays.resize(kept);
        }
}

void Executor::note_rays_held() {
    size_t held = 0;
    for (size_t c = 0; c < kComponentCount; ++c) held += bins_[c].size() + pending_[c].size();
    peak_rays_held_ = std::max(peak_rays_held_, held);
}

void Executor::run_camera_rays(const RayBatch& camera_rays) {
    execute_rays(camera_rays, true, kCameraAov, stats_.camera, "camera rays", std::nullopt);
    note_rays_held();
    if (options_.checkpoint) options_.checkpoint("camera rays", true);
}

void Executor::note_modulated(const sched::Node& node, double index, size_t found, size_t taken, double highest) {
    const std::string where = node.where.to_string();
    auto& steps = stats_.modulated;
    auto it = std::find_if(steps.begin(), steps.end(), [&](const ModulatedStep& m) { return m.where == where; });
    if (it == steps.end()) it = steps.insert(steps.end(), {where, node.component, index, modulate_n_, 0, 0, 0});
    it->index = std::min(it->index, index);
    it->found += found;
    it->taken += taken;
    it->highest_importance = std::max(it->highest_importance, highest);
}

bool Executor::exec(const sched::Node& node) {
    size_t c = static_cast<size_t>(node.component);
    RayBatch& bin = bins_[c];
    // The rays taken out run from a batch that is kept afterwards, so the bin refills into
    // memory it already owns instead of growing a new allocation at every step. The spare is
    // the component's own: with one spare for all, the large D batch passed from bin to bin
    // and D's bin regrew from a small one at every step, through fresh pages (page faults
    // and copies were 7 % of a Cornell box render).
    RayBatch take = std::move(spare_[c]);
    take.reset();
    struct KeepSpare {
        RayBatch& take;
        RayBatch& spare;
        ~KeepSpare() {
            take.reset();
            spare = std::move(take);
        }
    } keep_spare{take, spare_[c]};
    if (in_modulate_) {
        double index = node.first_index;
        for (const auto& [stride, iteration] : strides_) index += stride * static_cast<double>(iteration);
        RayBatch keep;
        double highest = 0;
        for (size_t i = 0; i < bin.size(); ++i) {
            const double imp = importance(bin.pixel[i]);
            highest = std::max(highest, imp);
            bool run = index < std::ceil(imp * modulate_n_);
            (run ? take : keep).push(bin.get(i));
        }
        if (!bin.empty()) note_modulated(node, index, bin.size(), take.size(), highest);
        bin = std::move(keep);
    } else {
        std::swap(take, bin);  // the bin continues in the spare's memory
    }
    if (take.empty()) return false;
    ComponentStats& stats = stats_.components[c];
    std::string letter(1, component_letter(node.component));
    auto put_back = [&](RayBatch& rays, size_t from) {  // skipped rays stay in their bin, in order
        if (from == 0 && bin.empty()) {
            bin = std::move(rays);  // the common case: a whole task skipped, nothing to copy
            return;
        }
        RayBatch rest;
        rest.append(rays, from, rays.size());
        rest.append(bin);
        bin = std::move(rest);
    };
    size_t first = 0;
    if (budget_active()) {
        double remaining = options_.budget_seconds - now();
        std::optional<double> cost = admission_cost(node.component);
        if (!cost) {
            // Pilot: the first 1 % of the rays, at least one chunk; its results are kept.
            size_t pilot = std::min(take.size(), std::max((take.size() + 99) / 100, chunk_rays()));
            RayBatch head;
            head.append(take, 0, pilot);
            ++stats.executions;
            stats_.steps.push_back({node.component, pilot});
            // Paced: a pilot of cache queries may make records for far longer than the budget.
            first = execute_rays(head, false, aov_of(node.component), stats, letter, node.component, true);
            if (first < pilot) {  // the budget was spent inside the pilot
                stats_.steps.back().rays = first;
                note_rays_skipped(letter, node, take.size() - first, take.size(), admission_cost(node.component).value_or(0));
                put_back(take, first);
                return first > 0;
            }
            if (first == take.size()) return true;
            remaining = options_.budget_seconds - now();
            cost = admission_cost(node.component);
        }
        double predicted = static_cast<double>(take.size() - first) * cost.value_or(0);
        if (predicted > remaining && options_.task_admission == ExecutorOptions::TaskAdmission::kBatches && cost.value_or(0) > 0)
            return run_in_batches(take, first, *cost, bin, stats, letter, node) || first > 0;
        if (predicted > remaining) {
            stats_.skipped.push_back({letter + " at " + node.where.to_string(), predicted, remaining});
            put_back(take, first);
            return first > 0;
        }
        if (first > 0) {  // the rest of a piloted step
            RayBatch rest;
            rest.append(take, first, take.size());
            stats_.steps.back().rays += rest.size();
            execute_rays(rest, false, aov_of(node.component), stats, letter, node.component);
            return true;
        }
    }
    ++stats.executions;
    stats_.steps.push_back({node.component, take.size()});
    execute_rays(take, false, aov_of(node.component), stats, letter, node.component);
    return true;
}

void Executor::note_rays_skipped(const std::string& letter, const sched::Node& node, size_t left, size_t of, double cost) {
    stats_.skipped.push_back({fmt::format("{} at {} ({} of {} rays)", letter, node.where.to_string(), left, of), static_cast<double>(left) * cost,
                              options_.budget_seconds - now()});
}

RayBatch Executor::by_importance(const RayBatch& rays, size_t first) const {
    std::vector<uint32_t> order(rays.size() - first);
    std::iota(order.begin(), order.end(), static_cast<uint32_t>(first));
    std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return importance(rays.pixel[a]) > importance(rays.pixel[b]); });
    RayBatch out;
    for (uint32_t i : order) out.push(rays.get(i));
    return out;
}

bool Executor::run_in_batches(RayBatch& take, size_t first, double cost, RayBatch& bin, ComponentStats& stats,
                              const std::string& letter, const sched::Node& node) {
    // Thesis 5.5: the rays of the most important pixels first (stable, so ties keep their
    // order and the choice is deterministic), in batches of about 1/32 of the task, each
    // admitted on the cost per ray while it fits (shrinking near the end); the rest stay in
    // the bin.
    // Without an importance map every pixel ties: the rays keep their order and are not
    // copied (sorting and copying a large task cost more than a batch, and overran budgets).
    const RayBatch reordered = options_.importance ? by_importance(take, first) : RayBatch{};
    const RayBatch& sorted = options_.importance ? reordered : take;
    const size_t start = options_.importance ? 0 : first;
    const size_t batch = std::max(chunk_rays(), (sorted.size() - start + 31) / 32);
    size_t done = start;
    while (done < sorted.size()) {
        size_t n = std::min(batch, sorted.size() - done);
        const double remaining = options_.budget_seconds - now();
        // Near the end a batch shrinks to half the time left (at least 256 rays), so the last
        // decisions land close to the budget instead of a whole batch's error away from it.
        const size_t fits = remaining > 0 ? static_cast<size_t>(0.5 * remaining / cost) : 0;
        if (fits < std::min<size_t>(256, n)) break;
        n = std::min(n, fits);
        RayBatch b;
        b.append(sorted, done, done + n);
        ++stats.executions;
        stats_.steps.push_back({node.component, n});
        const size_t ran = execute_rays(b, false, aov_of(node.component), stats, letter, node.component, true);
        done += ran;
        if (ran < n) break;  // the budget is spent
    }
    if (done < sorted.size()) {
        note_rays_skipped(letter, node, sorted.size() - done, sorted.size() - start, cost);
        RayBatch rest;
        rest.append(sorted, done, sorted.size());
        rest.append(bin);
        bin = std::move(rest);
    }
    return done > start;
}

void components_read(const sched::Node& n, std::array<bool, kComponentCount>& out) {
    if (n.op == sched::Op::kExec) out[static_cast<size_t>(n.component)] = true;
    for (const auto& c : n.children) components_read(c, out);
}

bool Executor::run_stage(const sched::Node& program) {
    if (options_.task_admission == ExecutorOptions::TaskAdmission::kQueues && budget_active()) return run_queues(program);
    return run(program);
}

bool Executor::run_queues(const sched::Node& program) {
    // Thesis 8.3: one queue per component the crex reads, its rays ordered by pixel importance
    // (stable: ties keep their order, so choices are deterministic). Each choice takes a batch
    // (an eighth of the queue, at least a chunk) from the queue worth the most luminance per
    // second as measured so far; a queue never measured goes first, as a pilot of one chunk.
    // A batch that does not fit the time left shrinks to what does; below a small floor its
    // queue is done, and the others are still considered.
    std::array<bool, kComponentCount> reads{};
    components_read(program, reads);
    std::array<bool, kComponentCount> out_of_time{};
    const size_t floor_rays = std::max<size_t>(64, chunk_rays() / 64);
    bool work = false;
    for (;;) {
        QueueChoice choice{};
        int best = -1;
        double best_value = -1;
        for (size_t c = 0; c < kComponentCount; ++c) {
            choice.value[c] = NAN;
            if (!reads[c] || bins_[c].empty() || out_of_time[c]) continue;
            const ComponentStats& st = stats_.components[c];
            std::optional<double> cost = admission_cost(static_cast<Component>(c));
            double value = !cost || st.rays == 0 || !(*cost > 0) ? INFINITY : st.luminance / static_cast<double>(st.rays) / *cost;
            choice.value[c] = value;
            if (value > best_value) best = static_cast<int>(c), best_value = value;
        }
        if (best < 0) break;
        const auto component = static_cast<Component>(best);
        RayBatch& bin = bins_[static_cast<size_t>(best)];
        std::optional<double> cost = admission_cost(component);
        size_t n = std::min(bin.size(), cost ? std::max(chunk_rays(), (bin.size() + 7) / 8) : chunk_rays());
        const double remaining = options_.budget_seconds - now();
        if (cost && static_cast<double>(n) * *cost > remaining) {
            n = remaining > 0 ? static_cast<size_t>(remaining / *cost) : 0;
            if (n < std::min(floor_rays, bin.size())) {
                out_of_time[static_cast<size_t>(best)] = true;
                continue;
            }
        }
        // Children of a batch join their queue's end, so a queue is put in importance order
        // again before a part of it is taken; a whole queue, or one of equal importance
        // everywhere, moves as it is (sorting and copying every choice cost 30 % of the time).
        RayBatch batch, rest;
        if (n == bin.size()) {
            batch = std::move(bin);
        } else if (!options_.importance) {
            batch.append(bin, 0, n);
            rest.append(bin, n, bin.size());
        } else {
            const RayBatch sorted = by_importance(bin, 0);
            batch.append(sorted, 0, n);
            rest.append(sorted, n, sorted.size());
        }
        bin = std::move(rest);
        ComponentStats& stats = stats_.components[static_cast<size_t>(best)];
        ++stats.executions;
        stats_.steps.push_back({component, n});
        choice.component = component;
        choice.rays = n;
        stats_.queue_choices.push_back(choice);
        std::string letter(1, component_letter(component));
        const size_t ran = execute_rays(batch, false, aov_of(component), stats, letter, component, true);
        if (ran < batch.size()) {  // the budget is spent: the rest goes back to the front of its queue
            RayBatch back;
            back.append(batch, ran, batch.size());
            back.append(bin);
            bin = std::move(back);
            out_of_time[static_cast<size_t>(best)] = true;
            stats_.steps.back().rays = ran;
            stats_.queue_choices.back().rays = ran;
        }
        note_rays_held();
        if (options_.checkpoint) options_.checkpoint(letter + " (queue)", true);
        work = true;
    }
    for (size_t c = 0; c < kComponentCount; ++c)
        if (reads[c] && !bins_[c].empty()) {
            std::optional<double> cost = admission_cost(static_cast<Component>(c));
            stats_.skipped.push_back({fmt::format("{} queue ({} rays)", component_letter(static_cast<Component>(c)), bins_[c].size()),
                                      static_cast<double>(bins_[c].size()) * cost.value_or(0), options_.budget_seconds - now()});
        }
    return work;
}

bool Executor::run_deferred(const sched::Node& node, bool owns) {
    if (!owns || deferring_) {
        bool work = false;
        for (const auto& child : node.children) work |= run(child);
        return work;
    }
    deferring_ = true;
    bool work = false;
    for (const auto& child : node.children) work |= run(child);
    deferring_ = false;
    for (size_t c = 0; c < kComponentCount; ++c) {
        bins_[c].append(pending_[c]);
        pending_[c].reset();
    }
    return work;
}

bool Executor::budgeted_group(const sched::Node& node, bool owns) {
    if (!budget_active()) return run_deferred(node, owns);
    std::array<bool, kComponentCount> reads{};
    components_read(node, reads);
    double predicted = 0;
    bool known = true;
    for (size_t c = 0; c < kComponentCount; ++c) {
        if (!reads[c]) continue;
        auto cost = admission_cost(static_cast<Component>(c));
        if (!cost) known = false;
        else predicted += static_cast<double>(bins_[c].size()) * *cost;
    }
    double remaining = options_.budget_seconds - now();
    if (known && predicted > remaining) {
        stats_.skipped.push_back({sched::to_crex(node) + " at " + node.where.to_string(), predicted, remaining});
        return false;
    }
    in_admitted_group_ = true;
    bool work = run_deferred(node, owns);
    in_admitted_group_ = false;
    return work;
}

bool Executor::run(const sched::Node& node) {
    using sched::Op;
    switch (node.op) {
    case Op::kExec: {
        bool work = exec(node);
        note_rays_held();
        if (work && options_.checkpoint)
            options_.checkpoint(fmt::format("{} at {}", component_letter(node.component), node.where.to_string()), true);
        return work;
    }
    case Op::kSeq: {
        bool work = false;
        for (const auto& child : node.children) work |= run(child);
        return work;
    }
    case Op::kDefer: return run_deferred(node, true);
    case Op::kBudgeted: return budgeted_group(node, node.owns_deferral);
    case Op::kModulate: {
        bool saved_in = in_modulate_;
        double saved_n = modulate_n_;
        auto saved_strides = std::move(strides_);
        in_modulate_ = true;
        modulate_n_ = node.occurrences;
        strides_.clear();
        bool work = false;
        for (const auto& child : node.children) work |= run(child);
        in_modulate_ = saved_in;
        modulate_n_ = saved_n;
        strides_ = std::move(saved_strides);
        return work;
    }
    case Op::kRepeat: {
        bool work = false;
        bool numbered = in_modulate_ && node.stride > 0;
        if (numbered) strides_.push_back({node.stride, 0});
        for (uint64_t k = 0; k < node.count; ++k) {
            if (numbered) strides_.back().second = k;
            // An iteration that took no ray left every bin as it found it, and a later one can
            // only do less (a higher `{ }` occurrence executes a subset, a budget has less time):
            // the rest of the count costs nothing (D2147483647 on empty bins used to spin).
            if (!run(node.children.front())) break;
            work = true;
        }
        if (numbered) strides_.pop_back();
        return work;
    }
    case Op::kRepeatUntilEmpty: {
        bool any = false;
        for (uint32_t k = 0;; ++k) {
            if (k >= node.cap) {
                warnings_.push_back(run_diagnostic("W401", node.where.to_string(),
                                                   fmt::format("'*' stopped after {} iterations (the cap) with work left", node.cap)));
                break;
            }
            bool work = run(node.children.front());
            any |= work;
            if (!work) break;
        }
        return any;
    }
    }
    return false;
}

}  // namespace crex

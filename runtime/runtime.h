/// \file runtime.h
/// The runtime's public API, one header for the layer: what `crex run`, the Python module and
/// programs (examples/api/) call. A render, in the order a program takes the steps:
///   1. load_scene_input(spec)                    runtime/api/run_inputs.h (a scene: JSON, RADIANCE, OBJ, builtin)
///   2. compile_pipeline(source, &scene_facts)    compiler/compiler.h (or compile_crex), or
///      load_run_inputs(InputSpec)                both at once, as `crex run` reads them
///   3. run_plan(plan, scene, RunOptions, group, observer)  runtime/api/run.h: options are typed
///      overrides of the plan's settings (run_options.h); group is a LocalGroup for one process
///      (runtime/driver/process_group.h; distributed: runtime/distributed/distributed.h);
///      observer sees progress and takes checkpoints (runtime/driver/run_observer.h)
///   4. the result's buffers: RunResult::image(), aov_image(), maps, film (samples per pixel),
///      and its summary (run_summary.h), or write_run_files() (run_outputs.h): images, profile,
///      maps, report, all or none
/// Images compare with the metrics of runtime/metrics/metrics.h.
#pragma once

#include "base/render_text.h"
#include "compiler/compiler.h"
#include "runtime/api/compare_files.h"
#include "runtime/api/equal_time.h"
#include "runtime/api/frame_sequence.h"
#include "runtime/api/resume.h"
#include "runtime/api/run.h"
#include "runtime/api/run_inputs.h"
#include "runtime/api/run_options.h"
#include "runtime/api/run_outputs.h"
#include "runtime/api/run_summary.h"
#include "runtime/api/sequence_outputs.h"
#include "runtime/driver/process_group.h"
#include "runtime/driver/run_observer.h"
#include "runtime/driver/run_plan.h"
#include "runtime/io/image_io.h"
#include "runtime/metrics/metrics.h"
#include "runtime/scene/census.h"

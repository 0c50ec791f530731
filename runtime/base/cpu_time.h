/// \file cpu_time.h
/// The process's CPU time, all threads together: what a share of a render's work is measured
/// against (wall time counts a thread waiting for a core as work).
#pragma once

namespace crex {

/// User plus system CPU seconds this process has used so far.
double process_cpu_seconds();

}  // namespace crex

/// \file fake_clock.h
/// A run clock that counts rays, for budget tests that must not depend on the machine's speed.
#pragma once

#include <cstdint>

namespace crex::testing {

/// One microsecond a ray: the executor's progress callback sets `rays`, its clock reads now().
struct FakeClock {
    uint64_t rays = 0;
    double now() const { return static_cast<double>(rays) * 1e-6; }
};

}  // namespace crex::testing

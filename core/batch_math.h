// Elementary functions over small batches of doubles, vectorised by SLEEF (Debian's
// libsleef-dev; Shibata and Petrogalli 2020, "SLEEF: A Portable Vectorized Library of C Standard
// Mathematical Functions", IEEE TPDS 31(6)). glibc's atan2 costs about 20 ns a call here (it
// switches the rounding mode on every call); SLEEF's two-lane atan2 about 4 ns a value, with an
// error of at most 3.5 ulp.
#pragma once

#include <array>
#include <cstddef>

namespace penumbra {

inline constexpr size_t kAtan2BatchSize = 4;
using Atan2Batch = std::array<double, kAtan2BatchSize>;

// out[i] = atan2(y[i], x[i]) for every lane, within 3.5 ulp of the exact value.
Atan2Batch atan2Batch(const Atan2Batch& y, const Atan2Batch& x);

}  // namespace penumbra

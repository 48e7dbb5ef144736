// Seed derivation for the simulator: every random stream (odometry noise, each frame, each dust
// cell) gets its own well-mixed seed from the run's seed, so streams are independent of each other
// and of the order in which they are used.
#pragma once

#include <cstdint>

namespace fleetloc::sim {

// The SplitMix64 finalizer: a bijective 64-bit mix.
inline std::uint64_t SplitMix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// The seed of stream `stream` (a constant naming its purpose, or an index) of run seed `seed`.
inline std::uint64_t MixSeed(std::uint64_t seed, std::uint64_t stream) {
  return SplitMix64(SplitMix64(seed) ^ SplitMix64(stream + 0x5eed));
}

}  // namespace fleetloc::sim

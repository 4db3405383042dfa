// The original engine's reciprocal square root, and NormalVectors.
//
// The original normalises vectors with a table-seeded reciprocal square root
// instead of 1/sqrt. Its results differ from 1/sqrt in the last bits, and
// those bits reach plane normals written to .cm files and the signs of some
// predicates, so cmkit computes it the same way (from the published formula:
// a 512-entry seed table, then two Newton steps in double).
#include <array>
#include <cmath>

#include "cmkit/vec3.h"

namespace cmkit {
namespace {

// Table layout: the index is the low exponent bit plus the top 8 mantissa bits
// of the argument; the entry is the top 8 mantissa bits of 1/sqrt of the
// smallest float with that index, rounded, in place at bit 15.
constexpr int kLookupBits = 8;
constexpr int kExpPos = 23;
constexpr int kExpBias = 127;
constexpr int kLookupPos = kExpPos - kLookupBits;
constexpr int kSeedPos = kExpPos - 8;
constexpr int kTableSize = 2 << kLookupBits;
constexpr std::uint32_t kLookupMask = kTableSize - 1;

std::array<std::uint32_t, kTableSize> makeTable() {
  std::array<std::uint32_t, kTableSize> table{};
  for (int i = 0; i < kTableSize; ++i) {
    const std::uint32_t inBits = (std::uint32_t(kExpBias - 1) << kExpPos) | (std::uint32_t(i) << kLookupPos);
    float in;
    std::memcpy(&in, &inBits, sizeof in);
    const float out = float(1.0 / std::sqrt(double(in)));
    const std::uint32_t outBits = floatBits(out);
    table[size_t(i)] = ((outBits + (1u << (kSeedPos - 2))) >> kSeedPos & 0xFFu) << kSeedPos;
  }
  table[kTableSize / 2] = 0xFFu << kSeedPos;
  return table;
}

// Immutable after static initialisation (thread-safe to read).
const std::array<std::uint32_t, kTableSize> kInvSqrtTable = makeTable();

}  // namespace

// float, not Real, here and in the table: the seed is made from the bits of
// an IEEE single (exponent and mantissa positions), whatever Real is.
float compatInvSqrt(float x) {
  const std::uint32_t a = floatBits(x);
  const double y = double(x * 0.5f);
  const std::uint32_t seedBits =
      (((std::uint32_t(3 * kExpBias - 1) - ((a >> kExpPos) & 0xFFu)) >> 1) << kExpPos) |
      kInvSqrtTable[(a >> kLookupPos) & kLookupMask];
  float seed;
  std::memcpy(&seed, &seedBits, sizeof seed);
  double r = seed;
  r = r * (1.5 - r * r * y);
  r = r * (1.5 - r * r * y);
  return float(r);
}

void normalVectors(const Vec3& n, Vec3& right, Vec3& up) {
  const Real d = n.x * n.x + n.y * n.y;
  if (d == 0) {
    right = {1, 0, 0};
  } else {
    const Real inv = Vec3::invSqrt(d);
    right = {-n.y * inv, n.x * inv, 0};
  }
  up = right.cross(n);
}

}  // namespace cmkit

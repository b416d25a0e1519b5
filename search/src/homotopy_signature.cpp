#include "terratraj/search/homotopy_signature.hpp"

#include <algorithm>
#include <cstdint>

namespace terratraj::search {

namespace {
constexpr std::uint64_t kFnvOffset = 14695981039346656037ull;
constexpr std::uint64_t kFnvPrime = 1099511628211ull;

// Mixes the four bytes of a 32-bit value, least significant first (independent of the
// platform's byte order).
std::uint64_t fnvMix(std::uint64_t hash, std::uint32_t value) {
  for (int i = 0; i < 4; ++i) {
    hash ^= (value >> (8 * i)) & 0xffu;
    hash *= kFnvPrime;
  }
  return hash;
}
}  // namespace

void HomotopySignature::append(FrameCrossing crossing) {
  crossing.direction = crossing.direction < 0 ? -1 : +1;
  if (!crossings_.empty()) {
    const FrameCrossing& last = crossings_.back();
    if (last.frame == crossing.frame && last.direction == -crossing.direction) {
      crossings_.pop_back();
      return;
    }
  }
  crossings_.push_back(crossing);
}

void HomotopySignature::append(const HomotopySignature& other) {
  // Copy first: `other` may be *this.
  if (&other == this) {
    const std::vector<FrameCrossing> copy = other.crossings_;
    for (const FrameCrossing& c : copy) append(c);
    return;
  }
  for (const FrameCrossing& c : other.crossings_) append(c);
}

bool HomotopySignature::operator<(const HomotopySignature& other) const {
  if (crossings_.size() != other.crossings_.size()) {
    return crossings_.size() < other.crossings_.size();
  }
  for (std::size_t i = 0; i < crossings_.size(); ++i) {
    const FrameCrossing& a = crossings_[i];
    const FrameCrossing& b = other.crossings_[i];
    if (a.frame != b.frame) return a.frame < b.frame;
    if (a.direction != b.direction) return a.direction < b.direction;
  }
  return false;
}

std::size_t HomotopySignature::hash() const {
  std::uint64_t h = kFnvOffset;
  for (const FrameCrossing& c : crossings_) {
    h = fnvMix(h, static_cast<std::uint32_t>(c.frame));
    h = fnvMix(h, static_cast<std::uint32_t>(c.direction));
  }
  return static_cast<std::size_t>(h);
}

std::string HomotopySignature::toString() const {
  std::string text;
  for (const FrameCrossing& c : crossings_) {
    text += frameName(c.frame);
    text += c.direction < 0 ? '-' : '+';
  }
  return text;
}

std::string HomotopySignature::frameName(int frame) {
  if (frame < 0) return "?";
  // Bijective base 26: 1 -> a, 26 -> z, 27 -> aa (frame + 1 as the number).
  std::string name;
  long long n = static_cast<long long>(frame) + 1;
  while (n > 0) {
    --n;
    name.push_back(static_cast<char>('a' + n % 26));
    n /= 26;
  }
  std::reverse(name.begin(), name.end());
  return name;
}

}  // namespace terratraj::search

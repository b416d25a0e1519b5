#pragma once
// HomotopySignature: the word of reference-frame crossings of a path, the homotopy-class label
// of the topology-aware lattice (TAEASL, 002_... II; docs/homotopy.md).
//
// A path that crosses frame 0 counter-clockwise, then frame 3 clockwise, has the signature
// "a+d-". Crossing a frame and crossing it straight back cancel, so that the signature depends
// only on how the path winds around the obstacles, not on its wiggles. The empty signature is
// the paper's class "emptyset" (no net crossing).

#include <cstddef>
#include <string>
#include <vector>

namespace terratraj::search {

/// One crossing of a reference frame by a path.
struct FrameCrossing {
  int frame = 0;       ///< index of the frame in its ReferenceFrames, >= 0
  int direction = +1;  ///< +1: from the frame's right to its left (counter-clockwise about the
                       ///< anchor); -1: the other way
  bool operator==(const FrameCrossing& other) const {
    return frame == other.frame && direction == other.direction;
  }
  bool operator!=(const FrameCrossing& other) const { return !(*this == other); }
};

/// The reduced, ordered list of the frame crossings of a path. Value type: cheap to copy for
/// short words (one std::vector), comparable, hashable. Invariant: no two adjacent crossings
/// are of the same frame in opposite directions.
class HomotopySignature {
 public:
  HomotopySignature() = default;

  /// Appends one crossing: removes the last crossing instead if it is of the same frame in the
  /// opposite direction (a crossing straight back). A direction < 0 is stored as -1, any other
  /// as +1. Allocates only when the vector grows.
  void append(FrameCrossing crossing);
  /// Appends every crossing of `other`, in order, with the same cancellation (the signature of
  /// a path followed by another).
  void append(const HomotopySignature& other);
  /// Removes every crossing (keeps the capacity).
  void clear() { crossings_.clear(); }

  /// Whether the path has no net crossing (the paper's class emptyset).
  bool empty() const { return crossings_.empty(); }
  /// Number of crossings after cancellation.
  std::size_t size() const { return crossings_.size(); }
  /// The crossings, in path order.
  const std::vector<FrameCrossing>& crossings() const { return crossings_; }

  bool operator==(const HomotopySignature& other) const { return crossings_ == other.crossings_; }
  bool operator!=(const HomotopySignature& other) const { return !(*this == other); }
  /// A strict total order (shorter first, then lexicographic by frame, then direction), for
  /// ordered containers and deterministic reports.
  bool operator<(const HomotopySignature& other) const;

  /// FNV-1a (64 bit) over the (frame, direction) pairs, byte order fixed: the same value for
  /// the same signature on every run and platform (truncated where size_t has 32 bits).
  std::size_t hash() const;

  /// The signature as text: each crossing's frameName() followed by '+' or '-', e.g. "a+b-";
  /// the empty signature gives "".
  std::string toString() const;

  /// Name of a frame index, base 26 like spreadsheet columns: 0 -> "a", 25 -> "z", 26 -> "aa",
  /// 27 -> "ab", 701 -> "zz", 702 -> "aaa". A negative index gives "?".
  static std::string frameName(int frame);

 private:
  std::vector<FrameCrossing> crossings_;
};

/// HomotopySignature::hash() as a functor, for std::unordered_map / unordered_set.
struct HomotopySignatureHash {
  std::size_t operator()(const HomotopySignature& signature) const { return signature.hash(); }
};

}  // namespace terratraj::search

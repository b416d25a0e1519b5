#pragma once
// FlatHashMap: open addressing (linear probing) from 64-bit keys to values, for the lattice
// searches' node and edge tables. Grows by doubling at half load; no allocation between growths.
// Internal to the search library.

#include <cstdint>
#include <utility>
#include <vector>

namespace terratraj::search::detail {

template <typename Value>
class FlatHashMap {
 public:
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};

  explicit FlatHashMap(std::size_t capacity = 1024) { rehash(roundUp(capacity)); }

  /// The value of `key`, or nullptr. The pointer is valid until the next insert.
  Value* find(std::uint64_t key) {
    std::size_t slot = hash(key) & mask_;
    while (true) {
      if (keys_[slot] == key) return &values_[slot];
      if (keys_[slot] == kEmpty) return nullptr;
      slot = (slot + 1) & mask_;
    }
  }

  /// The value of `key`, inserted default-constructed if absent; second = whether inserted.
  std::pair<Value*, bool> insert(std::uint64_t key) {
    if (2 * (size_ + 1) > keys_.size()) rehash(2 * keys_.size());
    std::size_t slot = hash(key) & mask_;
    while (true) {
      if (keys_[slot] == key) return {&values_[slot], false};
      if (keys_[slot] == kEmpty) {
        keys_[slot] = key;
        values_[slot] = Value{};
        ++size_;
        return {&values_[slot], true};
      }
      slot = (slot + 1) & mask_;
    }
  }

  std::size_t size() const { return size_; }

 private:
  static std::size_t roundUp(std::size_t n) {
    std::size_t c = 16;
    while (c < n) c *= 2;
    return c;
  }
  static std::uint64_t hash(std::uint64_t x) {  // splitmix64 finaliser
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
  }
  void rehash(std::size_t capacity) {
    std::vector<std::uint64_t> keys(capacity, kEmpty);
    std::vector<Value> values(capacity);
    const std::size_t mask = capacity - 1;
    for (std::size_t i = 0; i < keys_.size(); ++i) {
      if (keys_[i] == kEmpty) continue;
      std::size_t slot = hash(keys_[i]) & mask;
      while (keys[slot] != kEmpty) slot = (slot + 1) & mask;
      keys[slot] = keys_[i];
      values[slot] = std::move(values_[i]);
    }
    keys_.swap(keys);
    values_.swap(values);
    mask_ = mask;
  }

  std::vector<std::uint64_t> keys_;
  std::vector<Value> values_;
  std::size_t mask_ = 0;
  std::size_t size_ = 0;
};

}  // namespace terratraj::search::detail

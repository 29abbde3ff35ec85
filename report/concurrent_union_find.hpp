// Union-find over a fixed range of ids that many threads may unite at once,
// emptied in constant time so that it can be used again and again on few of
// its ids.
//
// Linking is by id: the larger of two roots is linked under the smaller with
// one compare-and-swap, so every set's root is its smallest member, whatever
// the order in which threads united its members. Finding halves the path as
// it goes (a parent is replaced by its grandparent, which is never a larger
// id), so parents only ever move towards the root. After the threads are
// joined, find() gives the same roots as a serial union-find linking the
// same way would.
//
// The lock-free scheme is that of Anderson and Woll, "Wait-free parallel
// algorithms for the union-find problem" (STOC 1991), with linking by index
// as in Jaiganesh and Burtscher's ECL-CC (HPDC 2018). Each parent is stored
// with the round it was set in: clear() starts a new round, and a parent of
// an earlier round counts as none, so that clearing does not touch the ids
// that the last round used.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <utility>

namespace snag::report {

template <typename Id>
class ConcurrentUnionFind {
  static_assert(sizeof(Id) <= 4, "a parent and its round share 64 bits");

 public:
  /// Ids 0 .. size - 1, each a set of its own.
  explicit ConcurrentUnionFind(std::size_t size) : size_(size), parent_(new std::atomic<std::uint64_t>[size]()) {}

  /// Makes every id a set of its own again. Not to be called beside any
  /// other call.
  void clear() {
    if (++round_ != 0) return;
    for (std::size_t id = 0; id < size_; ++id) parent_[id].store(0, std::memory_order_relaxed);  // rounds wrapped
    round_ = 1;
  }

  /// The root of id's set: its smallest member once no thread unites.
  Id find(Id id) {
    for (;;) {
      const Id parent = parent_of(id);
      if (parent == id) return id;
      const Id grandparent = parent_of(parent);
      // A failed swap only means another thread shortened the path first.
      if (grandparent != parent) {
        std::uint64_t expected = entry(parent);
        parent_[id].compare_exchange_weak(expected, entry(grandparent), std::memory_order_acq_rel);
      }
      id = grandparent;
    }
  }

  /// The root of id's set, as find() gives it, but without shortening the
  /// path: it writes nothing, so that threads that read the same sets do not
  /// contend for them. Beside unite() calls, a root that has since been
  /// linked under another; two ids it gives one root are in one set.
  Id root_of(Id id) const {
    for (;;) {
      const Id parent = parent_of(id);
      if (parent == id) return id;
      id = parent;
    }
  }

  /// Joins the sets of a and b. Safe beside other unite() and find() calls.
  void unite(Id a, Id b) {
    for (;;) {
      a = find(a);
      b = find(b);
      if (a == b) return;
      if (a < b) std::swap(a, b);
      // Link a under b if a is still a root (its entry of an earlier round, or itself).
      std::uint64_t expected = parent_[a].load(std::memory_order_acquire);
      if (parent_in_round(expected, a) != a) continue;
      if (parent_[a].compare_exchange_strong(expected, entry(b), std::memory_order_acq_rel)) return;
    }
  }

 private:
  std::uint64_t entry(Id parent) const { return (std::uint64_t{round_} << 32) | parent; }
  Id parent_in_round(std::uint64_t stored, Id id) const {
    return (stored >> 32) == round_ ? static_cast<Id>(stored & 0xffffffffu) : id;
  }
  Id parent_of(Id id) const { return parent_in_round(parent_[id].load(std::memory_order_acquire), id); }

  std::size_t size_;
  std::unique_ptr<std::atomic<std::uint64_t>[]> parent_;
  std::uint32_t round_ = 1;  // entries start in round 0: no parent
};

}  // namespace snag::report

// Union-find over a fixed range of ids that many threads may unite at once.
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
// as in Jaiganesh and Burtscher's ECL-CC (HPDC 2018).
#pragma once

#include <atomic>
#include <cstddef>
#include <memory>
#include <utility>

namespace snag::report {

template <typename Id>
class ConcurrentUnionFind {
 public:
  /// Ids 0 .. size - 1, none of them in a set until reset().
  explicit ConcurrentUnionFind(std::size_t size) : parent_(new std::atomic<Id>[size]) {}

  /// Makes `id` a set of its own. Not to be called while another thread
  /// unites or finds `id`.
  void reset(Id id) { parent_[id].store(id, std::memory_order_relaxed); }

  /// The root of id's set: its smallest member once no thread unites.
  Id find(Id id) {
    for (;;) {
      Id parent = parent_[id].load(std::memory_order_acquire);
      if (parent == id) return id;
      const Id grandparent = parent_[parent].load(std::memory_order_acquire);
      // A failed swap only means another thread shortened the path first.
      if (grandparent != parent) parent_[id].compare_exchange_weak(parent, grandparent, std::memory_order_acq_rel);
      id = grandparent;
    }
  }

  /// Joins the sets of a and b. Safe beside other unite() and find() calls.
  void unite(Id a, Id b) {
    for (;;) {
      a = find(a);
      b = find(b);
      if (a == b) return;
      if (a < b) std::swap(a, b);
      Id expected = a;  // a is still a root: link it under b
      if (parent_[a].compare_exchange_strong(expected, b, std::memory_order_acq_rel)) return;
    }
  }

 private:
  std::unique_ptr<std::atomic<Id>[]> parent_;
};

}  // namespace snag::report

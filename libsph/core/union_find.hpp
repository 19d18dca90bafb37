#pragma once
// Disjoint sets over the indices [0, n) (union-find): union by size, find with path halving, so a
// sequence of m operations costs O(m alpha(n)). The root of a set depends on the order of the
// unions; smallest_member_labels() gives a label that does not (the smallest index of each set),
// for results that must not change with the order in which pairs are met.

#include <cstddef>
#include <utility>
#include <vector>

namespace sph {

class UnionFind {
 public:
  explicit UnionFind(std::size_t n) : parent_(n), size_(n, 1), sets_(n) {
    for (std::size_t i = 0; i < n; ++i) parent_[i] = i;
  }

  std::size_t n_elements() const { return parent_.size(); }
  /// Number of disjoint sets.
  std::size_t n_sets() const { return sets_; }

  /// Root of the set of i.
  std::size_t find(std::size_t i) {
    while (parent_[i] != i) {
      parent_[i] = parent_[parent_[i]];  // path halving
      i = parent_[i];
    }
    return i;
  }

  /// Merges the sets of a and b; false if they were one set already.
  bool unite(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return false;
    if (size_[a] < size_[b]) std::swap(a, b);
    parent_[b] = a;
    size_[a] += size_[b];
    --sets_;
    return true;
  }

  bool same_set(std::size_t a, std::size_t b) { return find(a) == find(b); }
  /// Number of elements in the set of i.
  std::size_t set_size(std::size_t i) { return size_[find(i)]; }

  /// Per element, the smallest index of its set (independent of the order of the unions).
  std::vector<std::size_t> smallest_member_labels() {
    const std::size_t n = parent_.size();
    std::vector<std::size_t> label_of_root(n, n);
    std::vector<std::size_t> label(n);
    for (std::size_t i = 0; i < n; ++i) {
      std::size_t& l = label_of_root[find(i)];
      if (l == n) l = i;  // the first member met in index order is the smallest
      label[i] = l;
    }
    return label;
  }

 private:
  std::vector<std::size_t> parent_;
  std::vector<std::size_t> size_;
  std::size_t sets_;
};

}  // namespace sph

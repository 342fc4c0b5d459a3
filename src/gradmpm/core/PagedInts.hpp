#pragma once
// An array of values over a large index range (a grid's nodes) that holds memory only
// where values were set: the range is cut into pages of 4096 entries, and a page is
// allocated on its first write of a value other than the default; unallocated pages read
// as the default. A distributed run's rank sets values only around its box of the grid,
// so it holds a few pages where a plain array would hold the whole grid (DofMap's
// node-to-equation map: 4 bytes per grid node on every rank before). A read is a shift,
// a mask and two loads: cheap enough for the assembly's per-node lookups. (Also the
// per-node sums of F-bar's weak-node supports and the regularisation's diagonal,
// grid/NodeSums.hpp: 9 bytes per grid node on every rank before.)
#include <algorithm>
#include <cstddef>
#include <memory>
#include <vector>

namespace gradmpm {

template <class T>
class Paged {
 public:
  static constexpr int page_bits = 12;
  static constexpr int page_size = 1 << page_bits;

  Paged() = default;
  Paged(int size, T fill)
      : size_(size), fill_(fill), absent_(page_size, fill), pages_((size + page_size - 1) / page_size, absent_.data()) {}
  // The page table points into this object's own storage: a copy copies the pages; a
  // move keeps them (moving the vectors keeps their buffers, so the pointers stay valid).
  Paged(const Paged& o)
      : size_(o.size_), fill_(o.fill_), absent_(o.absent_), pages_(o.pages_.size(), absent_.data()) {
    for (std::size_t p = 0; p < pages_.size(); ++p)
      if (o.pages_[p] != o.absent_.data()) {
        pages_[p] = allocate();
        std::copy(o.pages_[p], o.pages_[p] + page_size, pages_[p]);
      }
  }
  Paged& operator=(const Paged& o) {
    if (this != &o) *this = Paged(o);
    return *this;
  }
  Paged(Paged&&) = default;
  Paged& operator=(Paged&&) = default;

  int size() const { return size_; }
  T operator[](int i) const { return pages_[i >> page_bits][i & (page_size - 1)]; }
  /// Sets entry i (allocating its page unless `value` is the default there already).
  void set(int i, T value) {
    T*& page = pages_[i >> page_bits];
    if (page == absent_.data()) {
      if (value == fill_) return;
      page = allocate();
    }
    page[i & (page_size - 1)] = value;
  }
  /// Entry i, writable (its page allocated).
  T& at(int i) {
    T*& page = pages_[i >> page_bits];
    if (page == absent_.data()) page = allocate();
    return page[i & (page_size - 1)];
  }
  /// Allocates every page (for an operation over the whole range).
  void allocate_all() {
    for (T*& page : pages_)
      if (page == absent_.data()) page = allocate();
  }
  int num_pages() const { return static_cast<int>(pages_.size()); }
  /// Page p's entries (page_size of them; the last page's beyond size() unused); writable
  /// only once allocated.
  T* page(int p) { return pages_[p]; }
  const T* page(int p) const { return pages_[p]; }
  bool allocated(int p) const { return pages_[p] != absent_.data(); }
  /// Calls f(i, value) for every entry of the allocated pages, i ascending within
  /// [0, size()): the entries that may differ from the default (every other one reads as it).
  template <class F>
  void for_each_held(F&& f) const {
    for (int p = 0; p < num_pages(); ++p) {
      if (!allocated(p)) continue;
      const int first = p * page_size, last = std::min(size_, first + page_size);
      for (int i = first; i < last; ++i) f(i, pages_[p][i - first]);
    }
  }
  /// Bytes held in pages (not counting the page table).
  std::size_t bytes() const { return owned_.size() * page_size * sizeof(T); }

 private:
  T* allocate() {
    owned_.push_back(std::make_unique<T[]>(page_size));
    T* page = owned_.back().get();
    for (int k = 0; k < page_size; ++k) page[k] = fill_;
    return page;
  }

  int size_ = 0;
  T fill_{};
  std::vector<T> absent_;  ///< the shared page of unallocated ranges (all fill_)
  std::vector<T*> pages_;
  std::vector<std::unique_ptr<T[]>> owned_;
};

using PagedInts = Paged<int>;

}  // namespace gradmpm

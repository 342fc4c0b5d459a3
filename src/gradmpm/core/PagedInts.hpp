#pragma once
// An array of integers over a large index range (a grid's nodes) that holds memory only
// where values were set: the range is cut into pages of 4096 entries, and a page is
// allocated on its first write of a value other than the default; unallocated pages read
// as the default. A distributed run's rank sets values only around its box of the grid,
// so it holds a few pages where a plain array would hold the whole grid (DofMap's
// node-to-equation map: 4 bytes per grid node on every rank before). A read is a shift,
// a mask and two loads: cheap enough for the assembly's per-node lookups.
#include <algorithm>
#include <cstddef>
#include <memory>
#include <vector>

namespace gradmpm {

class PagedInts {
 public:
  static constexpr int page_bits = 12;
  static constexpr int page_size = 1 << page_bits;

  PagedInts() = default;
  PagedInts(int size, int fill)
      : size_(size), fill_(fill), absent_(page_size, fill), pages_((size + page_size - 1) / page_size, absent_.data()) {}
  // The page table points into this object's own storage: a copy copies the pages; a
  // move keeps them (moving the vectors keeps their buffers, so the pointers stay valid).
  PagedInts(const PagedInts& o)
      : size_(o.size_), fill_(o.fill_), absent_(o.absent_), pages_(o.pages_.size(), absent_.data()) {
    for (std::size_t p = 0; p < pages_.size(); ++p)
      if (o.pages_[p] != o.absent_.data()) {
        pages_[p] = allocate();
        std::copy(o.pages_[p], o.pages_[p] + page_size, pages_[p]);
      }
  }
  PagedInts& operator=(const PagedInts& o) {
    if (this != &o) *this = PagedInts(o);
    return *this;
  }
  PagedInts(PagedInts&&) = default;
  PagedInts& operator=(PagedInts&&) = default;

  int size() const { return size_; }
  int operator[](int i) const { return pages_[i >> page_bits][i & (page_size - 1)]; }
  /// Sets entry i (allocating its page unless `value` is the default there already).
  void set(int i, int value) {
    int*& page = pages_[i >> page_bits];
    if (page == absent_.data()) {
      if (value == fill_) return;
      page = allocate();
    }
    page[i & (page_size - 1)] = value;
  }
  /// Allocates every page (for an operation over the whole range).
  void allocate_all() {
    for (int*& page : pages_)
      if (page == absent_.data()) page = allocate();
  }
  int num_pages() const { return static_cast<int>(pages_.size()); }
  /// Page p's entries (page_size of them; the last page's beyond size() unused); writable
  /// only once allocated.
  int* page(int p) { return pages_[p]; }
  /// Bytes held in pages (not counting the page table).
  std::size_t bytes() const { return owned_.size() * page_size * sizeof(int); }

 private:
  int* allocate() {
    owned_.push_back(std::make_unique<int[]>(page_size));
    int* page = owned_.back().get();
    for (int k = 0; k < page_size; ++k) page[k] = fill_;
    return page;
  }

  int size_ = 0, fill_ = 0;
  std::vector<int> absent_;  ///< the shared page of unallocated ranges (all fill_)
  std::vector<int*> pages_;
  std::vector<std::unique_ptr<int[]>> owned_;
};

}  // namespace gradmpm

#include "gradmpm/io/Csv.hpp"

#include <fmt/format.h>

#include <stdexcept>

namespace gradmpm {

std::string CsvTable::header() const {
  std::string s;
  for (std::size_t c = 0; c < names_.size(); ++c) s += (c ? "," : "") + names_[c];
  return s + '\n';
}

std::string CsvTable::rows() const {
  std::string s;
  const std::size_t rows = columns_.empty() ? 0 : columns_[0].size();
  for (const auto& col : columns_)
    if (col.size() != rows) throw std::logic_error("CsvTable: columns of different lengths");
  for (std::size_t r = 0; r < rows; ++r) {
    for (std::size_t c = 0; c < columns_.size(); ++c)
      fmt::format_to(std::back_inserter(s), "{}{}", c ? "," : "", columns_[c][r]);
    s += '\n';
  }
  return s;
}

}  // namespace gradmpm

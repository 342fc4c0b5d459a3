#pragma once
// A column table written as CSV with a header row. Numbers use the shortest text
// that reads back to the same double, so CSV files lose no precision.
#include <string>
#include <vector>

#include "gradmpm/core/Types.hpp"

namespace gradmpm {

class CsvTable {
 public:
  void add(std::string name, std::vector<double> values) {
    names_.push_back(std::move(name));
    columns_.push_back(std::move(values));
  }
  void add(std::string name, const Vector& v) {
    add(std::move(name), std::vector<double>(v.data(), v.data() + v.size()));
  }
  /// The whole table as text; throws std::logic_error if the columns differ in length.
  std::string str() const { return header() + rows(); }
  /// Its header line, and its rows without it (a distributed run's ranks write theirs).
  std::string header() const;
  std::string rows() const;

 private:
  std::vector<std::string> names_;
  std::vector<std::vector<double>> columns_;
};

}  // namespace gradmpm

#pragma once
// Named arrays of a run's state, the content of a checkpoint (app/Checkpoint.hpp): real
// and integer arrays and texts, each under a path-like name ("points/position"). Every
// part of the program that carries state between load steps puts its arrays here and
// takes them back on restart; io/Hdf5Archive.hpp stores an archive as an HDF5 file.
//
// Reading is checked: a missing name or an array of the wrong length is an InputError
// naming the checkpoint file and the array, never a silently short state.
#include <Eigen/Core>
#include <map>
#include <string>
#include <vector>

namespace gradmpm {

class Archive {
 public:
  explicit Archive(std::string source = "checkpoint") : source_(std::move(source)) {}
  /// The file the archive was read from, for messages.
  const std::string& source() const { return source_; }

  void put(const std::string& name, std::vector<double> v) { reals_[name] = std::move(v); }
  void put(const std::string& name, std::vector<long long> v) { integers_[name] = std::move(v); }
  void put_text(const std::string& name, std::string text) { texts_[name] = std::move(text); }
  void put_real(const std::string& name, double v) { put(name, std::vector<double>{v}); }
  void put_integer(const std::string& name, long long v) { put(name, std::vector<long long>{v}); }

  bool has(const std::string& name) const { return reals_.count(name) || integers_.count(name) || texts_.count(name); }
  /// The array `name`; `size` >= 0 requires that many values.
  const std::vector<double>& reals(const std::string& name, long long size = -1) const;
  const std::vector<long long>& integers(const std::string& name, long long size = -1) const;
  const std::string& text(const std::string& name) const;
  double real(const std::string& name) const { return reals(name, 1)[0]; }
  long long integer(const std::string& name) const { return integers(name, 1)[0]; }

  /// Fixed-size Eigen objects (Vec<dim>, Mat3), flattened in Eigen's storage order.
  template <typename T>
  void put_objects(const std::string& name, const std::vector<T>& v) {
    std::vector<double> flat;
    flat.reserve(v.size() * T::SizeAtCompileTime);
    for (const T& x : v) flat.insert(flat.end(), x.data(), x.data() + T::SizeAtCompileTime);
    put(name, std::move(flat));
  }
  /// Reads `count` objects into `v`.
  template <typename T>
  void get_objects(const std::string& name, long long count, std::vector<T>& v) const {
    const std::vector<double>& flat = reals(name, count * T::SizeAtCompileTime);
    v.resize(count);
    for (long long i = 0; i < count; ++i)
      std::copy_n(flat.data() + i * T::SizeAtCompileTime, T::SizeAtCompileTime, v[i].data());
  }

  const std::map<std::string, std::vector<double>>& all_reals() const { return reals_; }
  const std::map<std::string, std::vector<long long>>& all_integers() const { return integers_; }
  const std::map<std::string, std::string>& all_texts() const { return texts_; }

 private:
  [[noreturn]] void missing(const std::string& name, const char* kind) const;
  std::string source_;
  std::map<std::string, std::vector<double>> reals_;
  std::map<std::string, std::vector<long long>> integers_;
  std::map<std::string, std::string> texts_;
};

}  // namespace gradmpm

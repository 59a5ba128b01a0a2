// A checkpoint's bytes: one function per kind of data says what it holds, and the same function
// writes it and reads it back (`ar(a, b, c)`), so that the two directions cannot drift apart.
// Plain data (trivially copyable, Eigen's fixed-size matrices, and structs that declare
// `using archive_bitwise = void;`) goes as its bytes; vectors, strings, pairs and optionals
// element by element; any other type through a `persist(Archive&, T&)` found by ADL.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace tc {

/// A checkpoint that cannot be read back: truncated, or written by code that stores other data.
struct ArchiveError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

template <class T>
struct ArchiveBitwise : std::bool_constant<std::is_trivially_copyable_v<T>> {};
template <class S, int R, int C, int O, int MR, int MC>
struct ArchiveBitwise<Eigen::Matrix<S, R, C, O, MR, MC>>
    : std::bool_constant<(R > 0 && C > 0 && std::is_arithmetic_v<S>)> {};
template <class T>
requires requires {
  typename T::archive_bitwise;
}
struct ArchiveBitwise<T> : std::true_type {};

class Archive {
 public:
  /// An archive to write.
  Archive() = default;
  /// An archive to read `bytes` back from.
  explicit Archive(std::string bytes) : bytes_(std::move(bytes)), loading_(true) {}

  bool loading() const { return loading_; }
  const std::string& bytes() const { return bytes_; }
  /// Everything read back (loading): a checkpoint with bytes left over is not this code's.
  bool at_end() const { return at_ == bytes_.size(); }

  void raw(void* data, std::size_t n) {
    if (!loading_) {
      bytes_.append(static_cast<const char*>(data), n);
      return;
    }
    if (n > bytes_.size() - at_) throw ArchiveError("truncated: the data ends early");
    std::memcpy(data, bytes_.data() + at_, n);
    at_ += n;
  }

  /// A section's name: written, or read and required to be `name` (a reader that meets another
  /// section stops there, naming both).
  void section(const std::string& name) {
    std::string found = name;
    (*this)(found);
    if (found != name) throw ArchiveError("section '" + name + "' expected, '" + found + "' found");
  }

  template <class... T>
  Archive& operator()(T&... values) {
    (one(values), ...);
    return *this;
  }

 private:
  template <class T>
  void one(T& v) {
    if constexpr (ArchiveBitwise<T>::value) {
      raw(&v, sizeof(T));
    } else {
      persist(*this, v);
    }
  }
  template <class T>
  void one(std::vector<T>& v) {
    std::size_t n = v.size();
    raw(&n, sizeof n);
    if (loading_) {
      // Every element takes a byte at least (a bitwise one its size): a longer list is not data.
      const std::size_t each = ArchiveBitwise<T>::value ? std::max<std::size_t>(sizeof(T), 1) : 1;
      if (n > (bytes_.size() - at_) / each)
        throw ArchiveError("truncated: a list longer than the data left");
      v.resize(n);
    }
    if constexpr (ArchiveBitwise<T>::value) {
      if (n > 0) raw(v.data(), n * sizeof(T));
    } else {
      for (T& e : v) one(e);
    }
  }
  void one(std::vector<bool>& v) {
    std::vector<char> c(v.begin(), v.end());
    one(c);
    v.assign(c.begin(), c.end());
  }
  void one(std::string& s) {
    std::size_t n = s.size();
    raw(&n, sizeof n);
    if (loading_) {
      if (n > bytes_.size() - at_)
        throw ArchiveError("truncated: a text longer than the data left");
      s.resize(n);
    }
    if (n > 0) raw(s.data(), n);
  }
  template <class A, class B>
  void one(std::pair<A, B>& p) {
    one(p.first);
    one(p.second);
  }
  template <class T>
  void one(std::optional<T>& o) {
    bool has = o.has_value();
    raw(&has, sizeof has);
    if (loading_) {
      if (has)
        o.emplace();
      else
        o.reset();
    }
    if (has) one(*o);
  }

  std::string bytes_;
  std::size_t at_ = 0;
  bool loading_ = false;
};

}  // namespace tc

#pragma once
// An id of one kind of thing (STYLE.md §9, after Drake's common/identifier.h and
// common/type_safe_index.h): each kind is its own type, so one kind cannot be passed where
// another is expected (an episode where an attempt is, an object where a platform is), and
// "none" is the default value, asked with valid(), not a -1 compared at each use.
// The number inside is the one on the wire and in the databases; value() gives it at those edges.
// Ids that number the entries of a table (scene-graph objects, platforms) index an IdVector
// (id_vector.h) directly, so no caller converts them to a size_t.

#include <compare>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <ostream>
#include <string>

namespace mtg {

template <class Tag, class Rep = int>
class TypedId {
 public:
  /// None.
  constexpr TypedId() = default;
  /// Any negative value is none.
  constexpr explicit TypedId(Rep value) : value_(value < 0 ? Rep(-1) : value) {}
  /// The id of the i-th entry of a table.
  static constexpr TypedId of_index(std::size_t i) { return TypedId(static_cast<Rep>(i)); }

  constexpr bool valid() const { return value_ >= 0; }
  constexpr Rep value() const { return value_; }
  /// Its position in the table it numbers; only for a valid id.
  constexpr std::size_t index() const { return static_cast<std::size_t>(value_); }

  friend constexpr auto operator<=>(TypedId, TypedId) = default;
  friend std::string to_string(TypedId id) { return std::to_string(id.value_); }
  friend std::ostream& operator<<(std::ostream& out, TypedId id) { return out << id.value_; }

 private:
  Rep value_ = -1;
};

/// The ids 0 .. n-1 of a table of n entries, for range-for.
template <class Id>
class IdRange {
 public:
  class iterator {
   public:
    // Dereferencing gives a value, not a reference: an input iterator by the old rules, a
    // forward one by C++20's (as std::views::iota's).
    using iterator_category = std::input_iterator_tag;
    using iterator_concept = std::forward_iterator_tag;
    using value_type = Id;
    using difference_type = std::ptrdiff_t;
    using pointer = const Id*;
    using reference = Id;
    constexpr iterator() = default;
    constexpr explicit iterator(std::size_t i) : i_(i) {}
    constexpr Id operator*() const { return Id::of_index(i_); }
    constexpr iterator& operator++() { ++i_; return *this; }
    constexpr iterator operator++(int) { iterator old = *this; ++i_; return old; }
    friend constexpr bool operator==(iterator, iterator) = default;

   private:
    std::size_t i_ = 0;
  };

  constexpr explicit IdRange(std::size_t n) : n_(n) {}
  constexpr iterator begin() const { return iterator(0); }
  constexpr iterator end() const { return iterator(n_); }
  constexpr std::size_t size() const { return n_; }

 private:
  std::size_t n_;
};

}  // namespace mtg

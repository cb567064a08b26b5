#pragma once
// An id of one kind of thing (STYLE.md §9, after Drake's common/identifier.h): each kind is its
// own type, so one kind cannot be passed where another is expected (an episode where an attempt
// is, say), and "none" is the default value, asked with valid(), not a -1 compared at each use.
// The number inside is the one on the wire and in the databases; value() gives it at those edges.

#include <compare>
#include <cstdint>
#include <ostream>
#include <string>

namespace mtg {

template <class Tag, class Rep = int>
class TypedId {
 public:
  /// None.
  constexpr TypedId() = default;
  constexpr explicit TypedId(Rep value) : value_(value) {}

  constexpr bool valid() const { return value_ >= 0; }
  constexpr Rep value() const { return value_; }

  friend constexpr auto operator<=>(TypedId, TypedId) = default;
  friend constexpr bool operator==(TypedId, TypedId) = default;
  friend std::string to_string(TypedId id) { return std::to_string(id.value_); }
  friend std::ostream& operator<<(std::ostream& out, TypedId id) { return out << id.value_; }

 private:
  Rep value_ = -1;
};

}  // namespace mtg

#pragma once
// A table whose entries are numbered by a TypedId (after Drake's TypeSafeIndex containers): the
// i-th entry is table[Id::of_index(i)], and only that id kind indexes it, so an object's id
// cannot read the platform table.

#include <cassert>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/util/typed_id.h"

namespace mtg {

template <class Id, class T>
class IdVector {
 public:
  using value_type = T;
  using reference = typename std::vector<T>::reference;  // a proxy for IdVector<Id, bool>
  using const_reference = typename std::vector<T>::const_reference;
  using iterator = typename std::vector<T>::iterator;
  using const_iterator = typename std::vector<T>::const_iterator;

  IdVector() = default;
  explicit IdVector(std::size_t n) : items_(n) {}
  IdVector(std::size_t n, const T& value) : items_(n, value) {}

  /// `id` must number an entry (checked in debug builds; at() checks always).
  reference operator[](Id id) {
    assert(contains(id));
    return items_[id.index()];
  }
  const_reference operator[](Id id) const {
    assert(contains(id));
    return items_[id.index()];
  }
  /// @throws std::out_of_range for an id that numbers no entry (none included).
  reference at(Id id) { return items_.at(checked(id)); }
  const_reference at(Id id) const { return items_.at(checked(id)); }
  /// Whether `id` numbers an entry.
  bool contains(Id id) const { return id.valid() && id.index() < items_.size(); }

  std::size_t size() const { return items_.size(); }
  bool empty() const { return items_.empty(); }
  IdRange<Id> ids() const { return IdRange<Id>(items_.size()); }

  void resize(std::size_t n) { items_.resize(n); }
  void resize(std::size_t n, const T& value) { items_.resize(n, value); }
  void assign(std::size_t n, const T& value) { items_.assign(n, value); }
  /// Appends `value` and returns its id.
  Id push_back(T value) {
    items_.push_back(std::move(value));
    return Id::of_index(items_.size() - 1);
  }
  reference front() { return items_.front(); }
  const_reference front() const { return items_.front(); }
  reference back() { return items_.back(); }
  const_reference back() const { return items_.back(); }

  iterator begin() { return items_.begin(); }
  iterator end() { return items_.end(); }
  const_iterator begin() const { return items_.begin(); }
  const_iterator end() const { return items_.end(); }

  friend bool operator==(const IdVector&, const IdVector&) = default;

 private:
  std::size_t checked(Id id) const {
    if (!id.valid()) throw std::out_of_range("no entry for an id that is none");
    return id.index();
  }

  std::vector<T> items_;
};

}  // namespace mtg

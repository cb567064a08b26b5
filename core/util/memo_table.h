#pragma once
// Results of a pure computation remembered by the exact bytes of its inputs. A hit hands back
// the value the computation gave the first time, bit for bit, so what a caller gets does not
// depend on whether, by whom or in what order the table was filled: a memo cannot change a
// deterministic result. Safe to share between threads; a value, once in, stays where it is.

#include <mutex>
#include <optional>
#include <shared_mutex>
#include <string>
#include <type_traits>
#include <unordered_map>

namespace mtg {

/// Appends the object representation of `value` (a trivially copyable type) to a memo key.
template <class T>
void append_key(std::string& key, const T& value) {
  static_assert(std::is_trivially_copyable_v<T>, "a memo key holds raw bytes");
  key.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

template <class Value>
class MemoTable {
 public:
  /// The value stored for `key`, made by `make()` and stored first when there is none. Two
  /// threads may both make a missing value; the first stored is kept (both are the same).
  template <class Make>
  const Value& get(const std::string& key, Make&& make) {
    {
      const std::shared_lock lock(mutex_);
      if (const auto it = values_.find(key); it != values_.end()) return it->second;
    }
    Value made = make();
    const std::unique_lock lock(mutex_);
    return values_.try_emplace(key, std::move(made)).first->second;
  }

  std::size_t size() const {
    const std::shared_lock lock(mutex_);
    return values_.size();
  }

 private:
  mutable std::shared_mutex mutex_;
  std::unordered_map<std::string, Value> values_;  // rehashing keeps elements where they are
};

/// A MemoTable that holds at most `capacity` values: when full, it forgets them all and starts
/// again. For results asked for again and again among many asked for once or twice (the regions
/// of the objects a Level 3 step did not disturb, among those of the objects it did): the ones
/// asked for often are back after a few questions, and memory stays bounded. A value is handed
/// out as a copy, since forgetting frees it.
template <class Value>
class BoundedMemoTable {
 public:
  explicit BoundedMemoTable(std::size_t capacity) : capacity_(capacity) {}

  template <class Make>
  Value get(const std::string& key, Make&& make) {
    {
      const std::shared_lock lock(mutex_);
      if (const auto it = values_.find(key); it != values_.end()) return it->second;
    }
    Value made = make();
    const std::unique_lock lock(mutex_);
    if (values_.size() >= capacity_) values_.clear();
    values_.try_emplace(key, made);
    return made;
  }

  std::size_t size() const {
    const std::shared_lock lock(mutex_);
    return values_.size();
  }

 private:
  const std::size_t capacity_;
  mutable std::shared_mutex mutex_;
  std::unordered_map<std::string, Value> values_;
};

/// A memo of one entry: the value for the last key asked about. For results that are large and
/// asked for again right away, but rarely later. Safe to share between threads.
template <class Value>
class MemoSlot {
 public:
  template <class Make>
  Value get(const std::string& key, Make&& make) {
    {
      const std::lock_guard lock(mutex_);
      if (value_ && key_ == key) return *value_;
    }
    Value made = make();
    const std::lock_guard lock(mutex_);
    key_ = key;
    value_ = made;
    return made;
  }

 private:
  std::mutex mutex_;
  std::string key_;
  std::optional<Value> value_;
};

}  // namespace mtg

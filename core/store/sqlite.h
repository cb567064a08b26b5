#pragma once
// A small RAII layer over SQLite: a database handle, prepared statements with typed binds, and
// transactions. Every failure throws mtg::Error naming the database file and SQLite's message.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

struct sqlite3;
struct sqlite3_stmt;

namespace mtg::store {

class Database;

class Statement {
 public:
  Statement(Database& db, std::string_view sql);
  ~Statement();
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  /// Binds by 1-based position; returns *this for chaining.
  Statement& bind(int index, std::int64_t value);
  Statement& bind(int index, double value);
  Statement& bind(int index, std::string_view value);
  /// Binds bytes as a BLOB (not text: no encoding is implied).
  Statement& bind_blob(int index, std::string_view bytes);

  /// Steps once: true while a row is available.
  bool step();
  /// Runs to completion (for INSERT/UPDATE) and resets for reuse.
  void run();
  void reset();

  std::int64_t column_int(int index) const;
  double column_double(int index) const;
  /// Whether the value is stored as a number (integer or real): not text, a blob or NULL, which
  /// column_int and column_double would read as 0 without a word.
  bool column_is_number(int index) const;
  std::string column_text(int index) const;
  std::string column_blob(int index) const;

 private:
  Database& db_;
  sqlite3_stmt* stmt_ = nullptr;
};

class Database {
 public:
  enum class Mode { kReadOnly, kReadWrite, kCreate };
  /// @throws mtg::Error if the file cannot be opened (or, read-only, does not exist).
  Database(const std::filesystem::path& file, Mode mode);
  ~Database();
  Database(const Database&) = delete;
  Database& operator=(const Database&) = delete;

  void exec(std::string_view sql);
  /// Rows changed by the last INSERT/UPDATE/DELETE.
  int changes() const;
  const std::filesystem::path& file() const { return file_; }
  sqlite3* handle() { return db_; }
  [[noreturn]] void fail(const std::string& what) const;

 private:
  std::filesystem::path file_;
  sqlite3* db_ = nullptr;
};

/// BEGIN on construction, ROLLBACK on destruction unless commit() was called.
class Transaction {
 public:
  explicit Transaction(Database& db) : db_(db) { db_.exec("BEGIN"); }
  ~Transaction();
  void commit();

 private:
  Database& db_;
  bool done_ = false;
};

}  // namespace mtg::store

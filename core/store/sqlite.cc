#include "core/store/sqlite.h"

#include <sqlite3.h>

#include "core/util/atomic_file.h"
#include "core/util/error.h"

namespace mtg::store {

Database::Database(const std::filesystem::path& file, Mode mode) : file_(file) {
  if (mode == Mode::kReadOnly && !std::filesystem::exists(file)) {
    throw Error(file.string() + ": no such database");
  }
  int flags = SQLITE_OPEN_READONLY;
  if (mode == Mode::kReadWrite) flags = SQLITE_OPEN_READWRITE;
  if (mode == Mode::kCreate) flags = SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE;
  if (mode != Mode::kReadOnly) {
    // A database is written in place, with its journals beside it: a link planted at any of
    // those names (a dangling marks.sqlite) would have SQLite create or write what it names.
    for (const char* suffix : {"", "-journal", "-wal", "-shm"}) require_plain_file(file.string() + suffix);
    flags |= SQLITE_OPEN_NOFOLLOW;
  }
  if (sqlite3_open_v2(file.c_str(), &db_, flags, nullptr) != SQLITE_OK) {
    const std::string message = db_ ? sqlite3_errmsg(db_) : "out of memory";
    sqlite3_close(db_);
    db_ = nullptr;
    throw Error(file.string() + ": cannot open database: " + message);
  }
  sqlite3_busy_timeout(db_, 5000);
}

Database::~Database() { sqlite3_close(db_); }

void Database::exec(std::string_view sql) {
  char* message = nullptr;
  if (sqlite3_exec(db_, std::string(sql).c_str(), nullptr, nullptr, &message) != SQLITE_OK) {
    const std::string what = message ? message : "unknown error";
    sqlite3_free(message);
    fail(what + " (in: " + std::string(sql.substr(0, 60)) + ")");
  }
}

int Database::changes() const { return sqlite3_changes(db_); }

void Database::fail(const std::string& what) const { throw Error(file_.string() + ": " + what); }

Statement::Statement(Database& db, std::string_view sql) : db_(db) {
  if (sqlite3_prepare_v2(db.handle(), sql.data(), static_cast<int>(sql.size()), &stmt_, nullptr) != SQLITE_OK) {
    db.fail(std::string(sqlite3_errmsg(db.handle())) + " (in: " + std::string(sql.substr(0, 60)) + ")");
  }
}

Statement::~Statement() { sqlite3_finalize(stmt_); }

Statement& Statement::bind(int index, std::int64_t value) {
  if (sqlite3_bind_int64(stmt_, index, value) != SQLITE_OK) db_.fail(sqlite3_errmsg(db_.handle()));
  return *this;
}
Statement& Statement::bind(int index, double value) {
  if (sqlite3_bind_double(stmt_, index, value) != SQLITE_OK) db_.fail(sqlite3_errmsg(db_.handle()));
  return *this;
}
Statement& Statement::bind(int index, std::string_view value) {
  if (sqlite3_bind_text(stmt_, index, value.data(), static_cast<int>(value.size()), SQLITE_TRANSIENT) != SQLITE_OK) {
    db_.fail(sqlite3_errmsg(db_.handle()));
  }
  return *this;
}

Statement& Statement::bind_blob(int index, std::string_view bytes) {
  if (sqlite3_bind_blob(stmt_, index, bytes.data(), static_cast<int>(bytes.size()), SQLITE_TRANSIENT) != SQLITE_OK) {
    db_.fail(sqlite3_errmsg(db_.handle()));
  }
  return *this;
}

bool Statement::step() {
  const int rc = sqlite3_step(stmt_);
  if (rc == SQLITE_ROW) return true;
  if (rc == SQLITE_DONE) return false;
  db_.fail(sqlite3_errmsg(db_.handle()));
}

void Statement::run() {
  while (step()) {
  }
  reset();
}

void Statement::reset() {
  sqlite3_reset(stmt_);
  sqlite3_clear_bindings(stmt_);
}

std::int64_t Statement::column_int(int index) const { return sqlite3_column_int64(stmt_, index); }
double Statement::column_double(int index) const { return sqlite3_column_double(stmt_, index); }
bool Statement::column_is_number(int index) const {
  const int type = sqlite3_column_type(stmt_, index);
  return type == SQLITE_INTEGER || type == SQLITE_FLOAT;
}
std::string Statement::column_text(int index) const {
  const auto* text = sqlite3_column_text(stmt_, index);
  return text ? std::string(reinterpret_cast<const char*>(text), static_cast<std::size_t>(sqlite3_column_bytes(stmt_, index)))
              : std::string();
}

std::string Statement::column_blob(int index) const {
  const auto* bytes = static_cast<const char*>(sqlite3_column_blob(stmt_, index));
  return bytes ? std::string(bytes, static_cast<std::size_t>(sqlite3_column_bytes(stmt_, index))) : std::string();
}

Transaction::~Transaction() {
  if (!done_) {
    try {
      db_.exec("ROLLBACK");
    } catch (...) {
      // The original error is what matters; a failed rollback leaves the file to be discarded.
    }
  }
}

void Transaction::commit() {
  db_.exec("COMMIT");
  done_ = true;
}

}  // namespace mtg::store

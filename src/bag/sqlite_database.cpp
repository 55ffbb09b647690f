#include "odometry_calibration/bag/sqlite_database.h"

#include <cstdio>
#include <stdexcept>

#include <sqlite3.h>

namespace odometry_calibration {

SqliteDatabase::SqliteDatabase(const std::string& path, Mode mode) : path_(path)
{
  // Read: immutable (no locks, no journal looked for), which also reads a file already
  // unlinked; the path as a URI, its reserved characters escaped.
  std::string name = path;
  int flags = SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE;
  if (mode == Mode::kRead) {
    name = "file:";
    for (const char c : path) {
      if (c == '%' || c == '?' || c == '#') {
        char escaped[4];
        std::snprintf(escaped, sizeof(escaped), "%%%02X", static_cast<unsigned char>(c));
        name += escaped;
      } else {
        name += c;
      }
    }
    name += "?immutable=1";
    flags = SQLITE_OPEN_READONLY | SQLITE_OPEN_URI;
  }
  const int status = sqlite3_open_v2(name.c_str(), &db_, flags | SQLITE_OPEN_NOMUTEX, nullptr);
  if (status != SQLITE_OK) {
    const std::string reason = db_ ? sqlite3_errmsg(db_) : sqlite3_errstr(status);
    sqlite3_close(db_);
    db_ = nullptr;
    throw std::runtime_error("rosbag2 file '" + path + "' cannot be opened: " + reason);
  }
}

SqliteDatabase::~SqliteDatabase()
{
  sqlite3_close(db_);
}

void SqliteDatabase::fail(const std::string& doing) const
{
  const int code = sqlite3_errcode(db_);
  std::string reason = sqlite3_errmsg(db_);
  if (code == SQLITE_NOTADB)
    reason = "not an SQLite database (" + reason + ")";
  else if (code == SQLITE_CORRUPT)
    reason = "the database is corrupted (" + reason + ")";
  throw std::runtime_error("rosbag2 file '" + path_ + "': " + doing + " failed: " + reason);
}

void SqliteDatabase::execute(const std::string& sql)
{
  char* message = nullptr;
  if (sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &message) != SQLITE_OK) {
    sqlite3_free(message);
    fail("'" + sql.substr(0, 60) + "'");
  }
}

SqliteStatement::SqliteStatement(const SqliteDatabase& database, const std::string& sql)
    : database_(database), sql_(sql)
{
  if (sqlite3_prepare_v2(database.handle(), sql.c_str(), -1, &statement_, nullptr) != SQLITE_OK)
    database_.fail("reading its tables ('" + sql_ + "')");
}

SqliteStatement::~SqliteStatement()
{
  sqlite3_finalize(statement_);
}

bool SqliteStatement::step()
{
  const int status = sqlite3_step(statement_);
  if (status == SQLITE_ROW)
    return true;
  if (status == SQLITE_DONE)
    return false;
  database_.fail("reading ('" + sql_ + "')");
}

void SqliteStatement::reset()
{
  sqlite3_reset(statement_);
}

void SqliteStatement::bind(int index, std::int64_t value)
{
  if (sqlite3_bind_int64(statement_, index, value) != SQLITE_OK)
    database_.fail("binding a value");
}

void SqliteStatement::bind(int index, const std::string& value)
{
  if (sqlite3_bind_text(statement_, index, value.data(), static_cast<int>(value.size()),
                        SQLITE_TRANSIENT) != SQLITE_OK)
    database_.fail("binding a text");
}

void SqliteStatement::bindBlob(int index, const void* data, std::size_t size)
{
  if (sqlite3_bind_blob64(statement_, index, data, size, SQLITE_STATIC) != SQLITE_OK)
    database_.fail("binding a blob");
}

std::int64_t SqliteStatement::integer(int column) const
{
  return sqlite3_column_int64(statement_, column);
}

std::string SqliteStatement::text(int column) const
{
  const unsigned char* text = sqlite3_column_text(statement_, column);
  return text ? std::string(reinterpret_cast<const char*>(text),
                            static_cast<std::size_t>(sqlite3_column_bytes(statement_, column)))
              : std::string();
}

const std::uint8_t* SqliteStatement::blob(int column, std::size_t& size) const
{
  const void* data = sqlite3_column_blob(statement_, column);
  size = data ? static_cast<std::size_t>(sqlite3_column_bytes(statement_, column)) : 0;
  return static_cast<const std::uint8_t*>(data);
}

}  // namespace odometry_calibration

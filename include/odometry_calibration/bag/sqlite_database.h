// A thin RAII layer over SQLite's C API (Debian's libsqlite3) for the rosbag2 storage: every
// failure becomes a std::runtime_error naming the database file and SQLite's own reason.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

struct sqlite3;
struct sqlite3_stmt;

namespace odometry_calibration {

/// One open database file.
class SqliteDatabase
{
public:
  enum class Mode
  {
    kRead,    ///< an existing file, read-only
    kCreate,  ///< read-write, the file created when missing
  };
  /// Opens `path`. Throws std::runtime_error naming it and the cause.
  SqliteDatabase(const std::string& path, Mode mode);
  ~SqliteDatabase();
  SqliteDatabase(const SqliteDatabase&) = delete;
  SqliteDatabase& operator=(const SqliteDatabase&) = delete;

  const std::string& path() const { return path_; }
  sqlite3* handle() const { return db_; }

  /// Runs `sql` (statements without results). Throws as fail().
  void execute(const std::string& sql);
  /// Throws std::runtime_error: "rosbag2 file '<path>': <doing> failed: <SQLite's message>",
  /// where a file that is not a database says so.
  [[noreturn]] void fail(const std::string& doing) const;

private:
  std::string path_;
  sqlite3* db_ = nullptr;
};

/// A prepared statement of a database (which must outlive it).
class SqliteStatement
{
public:
  /// Prepares `sql`. Throws as SqliteDatabase::fail (e.g. a missing table).
  SqliteStatement(const SqliteDatabase& database, const std::string& sql);
  ~SqliteStatement();
  SqliteStatement(const SqliteStatement&) = delete;
  SqliteStatement& operator=(const SqliteStatement&) = delete;

  /// The next row: true, or false after the last one. Throws on an error (a corrupted file).
  bool step();
  /// Back to before the first row, the bindings kept.
  void reset();

  /// Parameter `index` (from 1).
  void bind(int index, std::int64_t value);
  void bind(int index, const std::string& value);
  void bindBlob(int index, const void* data, std::size_t size);

  /// Column `column` (from 0) of the current row.
  std::int64_t integer(int column) const;
  std::string text(int column) const;
  /// The blob's bytes, valid until the next step() or reset(); `size` set to their count.
  const std::uint8_t* blob(int column, std::size_t& size) const;

private:
  const SqliteDatabase& database_;
  std::string sql_;
  sqlite3_stmt* statement_ = nullptr;
};

}  // namespace odometry_calibration

#include "odometry_calibration/bag/zstd_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <vector>

#include <zstd.h>

namespace odometry_calibration {
namespace {

struct FileCloser
{
  void operator()(std::FILE* file) const { std::fclose(file); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

File openFile(const std::string& path, const char* mode)
{
  File file(std::fopen(path.c_str(), mode));
  if (!file) {
    throw std::runtime_error("cannot " + std::string(mode[0] == 'r' ? "read" : "write") + " '" +
                             path + "': " + std::strerror(errno));
  }
  return file;
}

void writeAll(std::FILE* file, const void* data, std::size_t size, const std::string& path)
{
  if (size > 0 && std::fwrite(data, 1, size, file) != size)
    throw std::runtime_error("cannot write '" + path + "': " + std::strerror(errno));
}

/// Closes `file` (flushing it), throwing when the last writes failed (e.g. a full disk).
void closeWritten(File file, const std::string& path)
{
  if (std::fclose(file.release()) != 0)
    throw std::runtime_error("cannot write '" + path + "': " + std::strerror(errno));
}

}  // namespace

void decompressZstdFile(const std::string& from, const std::string& to)
{
  File in = openFile(from, "rb");
  File out = openFile(to, "wb");
  std::unique_ptr<ZSTD_DStream, decltype(&ZSTD_freeDStream)> stream(ZSTD_createDStream(),
                                                                    ZSTD_freeDStream);
  std::vector<char> input(ZSTD_DStreamInSize()), output(ZSTD_DStreamOutSize());
  std::size_t last = 1;  // 0 once a frame is complete
  bool any = false;
  for (std::size_t read; (read = std::fread(input.data(), 1, input.size(), in.get())) > 0;) {
    any = true;
    ZSTD_inBuffer in_buffer = {input.data(), read, 0};
    while (in_buffer.pos < in_buffer.size) {
      ZSTD_outBuffer out_buffer = {output.data(), output.size(), 0};
      last = ZSTD_decompressStream(stream.get(), &out_buffer, &in_buffer);
      if (ZSTD_isError(last)) {
        throw std::runtime_error("'" + from +
                                 "' does not decompress (zstd: " + ZSTD_getErrorName(last) + ")");
      }
      writeAll(out.get(), output.data(), out_buffer.pos, to);
    }
  }
  if (std::ferror(in.get()))
    throw std::runtime_error("cannot read '" + from + "': " + std::strerror(errno));
  if (!any || last != 0)
    throw std::runtime_error("'" + from + "' is cut off (its zstd stream does not end)");
  closeWritten(std::move(out), to);
}

void compressZstdFile(const std::string& from, const std::string& to, int level)
{
  File in = openFile(from, "rb");
  File out = openFile(to, "wb");
  std::unique_ptr<ZSTD_CStream, decltype(&ZSTD_freeCStream)> stream(ZSTD_createCStream(),
                                                                    ZSTD_freeCStream);
  ZSTD_initCStream(stream.get(), level);
  std::vector<char> input(ZSTD_CStreamInSize()), output(ZSTD_CStreamOutSize());
  // One call's output written out; returns what zstd still holds back (0: all flushed).
  auto compress = [&](ZSTD_inBuffer& in_buffer, ZSTD_EndDirective mode) {
    ZSTD_outBuffer out_buffer = {output.data(), output.size(), 0};
    const std::size_t remaining = ZSTD_compressStream2(stream.get(), &out_buffer, &in_buffer, mode);
    if (ZSTD_isError(remaining))
      throw std::runtime_error(std::string("zstd: ") + ZSTD_getErrorName(remaining));
    writeAll(out.get(), output.data(), out_buffer.pos, to);
    return remaining;
  };
  for (bool finished = false; !finished;) {
    const std::size_t read = std::fread(input.data(), 1, input.size(), in.get());
    if (std::ferror(in.get()))
      throw std::runtime_error("cannot read '" + from + "': " + std::strerror(errno));
    finished = read < input.size();
    ZSTD_inBuffer in_buffer = {input.data(), read, 0};
    while (in_buffer.pos < in_buffer.size)
      compress(in_buffer, ZSTD_e_continue);
  }
  ZSTD_inBuffer end = {nullptr, 0, 0};
  while (compress(end, ZSTD_e_end) != 0) {
  }
  closeWritten(std::move(out), to);
}

}  // namespace odometry_calibration

// Reading a whole input file: see cmkit/text_file.h.
#include "cmkit/text_file.h"

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <new>

namespace cmkit {

namespace {

/// "no such file", "permission denied", ... for the errno of a failed open.
std::string reasonOf(int error) {
  if (error == ENOENT) return "no such file";
  if (error == EACCES) return "permission denied (cannot open the file)";
  return std::string("cannot open the file: ") + std::strerror(error);
}

/// Appends the bytes of `f` to `text` until its end or maxBytes in all;
/// false on a read error (errno says which).
bool readStream(std::FILE* f, std::size_t maxBytes, std::string& text) {
  char buffer[1 << 16];
  while (text.size() < maxBytes) {
    const std::size_t want = std::min(sizeof buffer, maxBytes - text.size());
    const std::size_t n = std::fread(buffer, 1, want, f);
    text.append(buffer, n);
    if (n < want) break;
  }
  return std::ferror(f) == 0;
}

Result<std::string> readUpTo(const std::string& path, std::size_t maxBytes) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (fs::is_directory(status)) return Error("is a directory, not a file", path);
  errno = 0;
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return Error(reasonOf(errno), path);
  std::string text;
  // The size is only a hint (it can change, or be 0 for special files);
  // reading goes on to the end whatever it says.
  const std::uintmax_t size = fs::is_regular_file(status) ? fs::file_size(path, ec) : 0;
  if (!ec && size > 0) {
    if (size > text.max_size() && maxBytes > text.max_size()) {
      std::fclose(f);
      return Error("too large to read into memory", path);
    }
    text.reserve(std::size_t(std::min<std::uintmax_t>(size, maxBytes)));
  }
  const bool read = readStream(f, maxBytes, text);
  const int readError = errno;
  std::fclose(f);
  if (!read) return Error(std::string("cannot read the file: ") + std::strerror(readError), path);
  return text;
}

template <class Read>
Result<std::string> neverThrowing(const std::string& name, Read read) {
  try {
    return read();
  } catch (const std::bad_alloc&) {
    return Error("too large to read into memory", name);
  } catch (const std::exception& e) {
    return Error(std::string("cannot read the file: ") + e.what(), name);
  }
}

}  // namespace

Result<std::string> readTextFile(const std::string& path, std::size_t maxBytes) {
  return neverThrowing(path, [&] { return readUpTo(path, maxBytes); });
}

Result<std::string> readStandardInput(std::size_t maxBytes) {
  return neverThrowing("-", [&]() -> Result<std::string> {
    std::string text;
    if (!readStream(stdin, maxBytes, text))
      return Error(std::string("cannot read standard input: ") + std::strerror(errno), "-");
    return text;
  });
}

}  // namespace cmkit

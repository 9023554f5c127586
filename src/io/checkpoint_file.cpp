// The checkpoint container (include/talus/io/checkpoint_file.hpp). Layout:
//   "TALUSCK1"                                   8 bytes
//   records: u32 name length, name, u8 kind (1 f64, 2 i64, 3 text), u64 count, count values
//   trailer: u64 bytes before the trailer, u32 CRC-32 (zlib) of those bytes, "TCKEND\0\0"
#include "talus/io/checkpoint_file.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <fmt/format.h>
#include <fstream>
#include <stdexcept>
#include <unistd.h>
#include <zlib.h>

namespace talus {

namespace fs = std::filesystem;

namespace {

constexpr char kMagic[8] = {'T', 'A', 'L', 'U', 'S', 'C', 'K', '1'};
constexpr char kEnd[8] = {'T', 'C', 'K', 'E', 'N', 'D', '\0', '\0'};
constexpr std::size_t kTrailer = 8 + 4 + 8;
constexpr std::uint8_t kDoubles = 1, kIntegers = 2, kText = 3;

void append_bytes(std::vector<unsigned char>& out, const void* data, std::size_t n) {
  const std::size_t at = out.size();
  out.resize(at + n);
  if (n > 0)
    std::memcpy(out.data() + at, data, n);
}

template <class T> void append_raw(std::vector<unsigned char>& out, const T& value) {
  append_bytes(out, &value, sizeof(T));
}

template <class T> T read_raw(const std::vector<unsigned char>& in, std::size_t at) {
  T value;
  std::memcpy(&value, in.data() + at, sizeof(T));
  return value;
}

/// `crc` continued over n more bytes (zlib takes a uInt length: large inputs go in pieces).
unsigned long crc_of_more(unsigned long crc, const unsigned char* data, std::size_t n) {
  constexpr std::size_t kPiece = 1u << 30;
  for (std::size_t at = 0; at < n; at += kPiece)
    crc = crc32(crc, data + at, static_cast<uInt>(std::min(kPiece, n - at)));
  return crc;
}

std::uint32_t crc_of(const unsigned char* data, std::size_t n) {
  return static_cast<std::uint32_t>(crc_of_more(crc32(0L, Z_NULL, 0), data, n));
}

/// Writes all of `data` to fd; false (errno set) on failure.
bool write_all(int fd, const unsigned char* data, std::size_t n) {
  while (n > 0) {
    const ssize_t w = ::write(fd, data, n);
    if (w < 0) {
      if (errno == EINTR)
        continue;
      return false;
    }
    data += w;
    n -= static_cast<std::size_t>(w);
  }
  return true;
}

const char* kind_name(std::uint8_t kind) {
  return kind == kDoubles ? "numbers" : kind == kIntegers ? "integers" : "text";
}

} // namespace

/// Written to the file whenever the buffer holds this much.
constexpr std::size_t kBufferBytes = 1u << 20;

CheckpointWriter::CheckpointWriter(fs::path file)
    : file_(std::move(file)), tmp_(file_.string() + ".tmp") {
  fd_ = ::open(tmp_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0)
    fail("open");
  crc_ = crc32(0L, Z_NULL, 0);
  buffer_.reserve(kBufferBytes);
  append(kMagic, sizeof kMagic);
}

CheckpointWriter::~CheckpointWriter() {
  if (fd_ >= 0)
    ::close(fd_);
  if (!committed_)
    ::unlink(tmp_.c_str());
}

void CheckpointWriter::fail(const char* what) {
  const int err = errno;
  if (fd_ >= 0)
    ::close(fd_);
  fd_ = -1;
  ::unlink(tmp_.c_str());
  throw std::runtime_error(fmt::format("cannot write checkpoint '{}': {}: {}", file_.string(), what,
                                       std::strerror(err)));
}

void CheckpointWriter::flush() {
  crc_ = crc_of_more(crc_, buffer_.data(), buffer_.size());
  if (!write_all(fd_, buffer_.data(), buffer_.size()))
    fail("write");
  length_ += buffer_.size();
  buffer_.clear();
}

void CheckpointWriter::append(const void* data, std::size_t n) {
  const auto* p = static_cast<const unsigned char*>(data);
  while (n > 0) {
    const std::size_t take = std::min(n, kBufferBytes - buffer_.size());
    buffer_.insert(buffer_.end(), p, p + take);
    p += take;
    n -= take;
    if (buffer_.size() == kBufferBytes)
      flush();
  }
}

void CheckpointWriter::record(const std::string& name, std::uint8_t kind, std::uint64_t count,
                              const void* data, std::size_t bytes) {
  if (fd_ < 0 || committed_)
    throw std::logic_error("CheckpointWriter: entry '" + name + "' after commit or a failure");
  const auto name_length = static_cast<std::uint32_t>(name.size());
  append(&name_length, sizeof name_length);
  append(name.data(), name.size());
  append(&kind, sizeof kind);
  append(&count, sizeof count);
  append(data, bytes);
}

void CheckpointWriter::put(const std::string& name, std::span<const double> values) {
  record(name, kDoubles, values.size(), values.data(), values.size_bytes());
}

void CheckpointWriter::put(const std::string& name, std::span<const std::int64_t> values) {
  record(name, kIntegers, values.size(), values.data(), values.size_bytes());
}

void CheckpointWriter::put_text(const std::string& name, const std::string& text) {
  record(name, kText, text.size(), text.data(), text.size());
}

void CheckpointWriter::commit() {
  flush();
  std::vector<unsigned char> trailer;
  append_raw(trailer, length_);
  append_raw(trailer, static_cast<std::uint32_t>(crc_));
  append_bytes(trailer, kEnd, sizeof kEnd);
  if (!write_all(fd_, trailer.data(), trailer.size()))
    fail("write");
  if (::fsync(fd_) != 0)
    fail("fsync");
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0)
    fail("close");
  if (::rename(tmp_.c_str(), file_.c_str()) != 0)
    fail("rename");
  committed_ = true;
  // The rename itself reaches the disk with the directory's entry.
  const int dir = ::open(file_.parent_path().empty() ? "." : file_.parent_path().c_str(),
                         O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir >= 0) {
    ::fsync(dir);
    ::close(dir);
  }
}

std::optional<CheckpointReader> CheckpointReader::open(const fs::path& file, std::string& why) {
  CheckpointReader r;
  r.file_ = file;
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    why = "cannot be opened";
    return std::nullopt;
  }
  r.bytes_.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  auto& b = r.bytes_;
  if (b.size() < sizeof kMagic + kTrailer || std::memcmp(b.data(), kMagic, sizeof kMagic) != 0) {
    why = fmt::format("is not a Talus checkpoint ({} bytes)", b.size());
    return std::nullopt;
  }
  const std::size_t body = b.size() - kTrailer;
  if (std::memcmp(b.data() + b.size() - sizeof kEnd, kEnd, sizeof kEnd) != 0 ||
      read_raw<std::uint64_t>(b, body) != body) {
    why = fmt::format("is truncated or damaged: no valid end record ({} bytes)", b.size());
    return std::nullopt;
  }
  if (read_raw<std::uint32_t>(b, body + 8) != crc_of(b.data(), body)) {
    why = "is corrupt: its checksum does not match its contents";
    return std::nullopt;
  }
  std::size_t at = sizeof kMagic;
  while (at < body) {
    if (at + 4 > body)
      break;
    const auto name_length = read_raw<std::uint32_t>(b, at);
    at += 4;
    if (at + name_length + 1 + 8 > body)
      break;
    const std::string name(reinterpret_cast<const char*>(b.data() + at), name_length);
    at += name_length;
    Entry e;
    e.kind = b[at];
    e.count = read_raw<std::uint64_t>(b, at + 1);
    at += 9;
    const std::size_t width = e.kind == kText ? 1 : 8;
    if (e.kind < kDoubles || e.kind > kText || e.count > (body - at) / width)
      break;
    e.offset = at;
    at += e.count * width;
    r.entries_[name] = e;
  }
  if (at != body) {
    why = "is damaged: a record runs past its end";
    return std::nullopt;
  }
  return r;
}

const CheckpointReader::Entry& CheckpointReader::entry(const std::string& name,
                                                       std::uint8_t kind) const {
  const auto it = entries_.find(name);
  if (it == entries_.end())
    throw std::runtime_error(
        fmt::format("checkpoint '{}' has no entry '{}'", file_.string(), name));
  if (it->second.kind != kind)
    throw std::runtime_error(fmt::format("checkpoint '{}': entry '{}' holds {}, not {}",
                                         file_.string(), name, kind_name(it->second.kind),
                                         kind_name(kind)));
  return it->second;
}

std::vector<double> CheckpointReader::doubles(const std::string& name) const {
  const Entry& e = entry(name, kDoubles);
  std::vector<double> out(e.count);
  if (e.count > 0) // memcpy may not be given the null data() of an empty vector
    std::memcpy(out.data(), bytes_.data() + e.offset, e.count * sizeof(double));
  return out;
}

std::vector<std::int64_t> CheckpointReader::integers(const std::string& name) const {
  const Entry& e = entry(name, kIntegers);
  std::vector<std::int64_t> out(e.count);
  if (e.count > 0)
    std::memcpy(out.data(), bytes_.data() + e.offset, e.count * sizeof(std::int64_t));
  return out;
}

std::int64_t CheckpointReader::integer(const std::string& name) const {
  const auto v = integers(name);
  if (v.size() != 1)
    throw std::runtime_error(fmt::format("checkpoint '{}': entry '{}' holds {} integers, not one",
                                         file_.string(), name, v.size()));
  return v[0];
}

std::string CheckpointReader::text(const std::string& name) const {
  const Entry& e = entry(name, kText);
  return {reinterpret_cast<const char*>(bytes_.data() + e.offset), e.count};
}

std::string checkpoint_name(Index step) {
  return fmt::format("checkpoint_{:09d}.tck", step);
}

std::vector<fs::path> list_checkpoints(const fs::path& dir) {
  std::vector<fs::path> out;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.starts_with("checkpoint_") && name.ends_with(".tck"))
      out.push_back(entry.path());
  }
  // The step is zero-padded: the names sort by step.
  std::sort(out.begin(), out.end(), std::greater<>());
  return out;
}

} // namespace talus

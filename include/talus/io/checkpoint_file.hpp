#pragma once
// The checkpoint container: named arrays of doubles, 64-bit integers or text, written
// atomically (a temporary file, flushed to disk, renamed over the name) and closed by a trailer
// with the payload's length and CRC-32, so a truncated or corrupt file is recognised and never
// half-read. The bytes are little-endian as the machine writes them; the layout is in
// docs/output-format.md ("Checkpoints"). What a run stores in it: solver/scene_checkpoint.hpp
// (the points) and src/solver/run_checkpoint.hpp (the run's progress).
#include "talus/core/types.hpp"

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace talus {

/// A checkpoint being written: the entries stream into `file`.tmp as they are put (a buffer of
/// at most 1 MiB, so a checkpoint costs little memory beyond the arrays it is given), and
/// commit() makes it `file`. A writer destroyed without commit() removes its temporary file.
/// Every failure (a full disk, say) throws std::runtime_error naming the file and the system's
/// reason; the file that was there before is then untouched.
class CheckpointWriter {
public:
  explicit CheckpointWriter(std::filesystem::path file);
  ~CheckpointWriter();
  CheckpointWriter(const CheckpointWriter&) = delete;
  CheckpointWriter& operator=(const CheckpointWriter&) = delete;

  void put(const std::string& name, std::span<const double> values);
  void put(const std::string& name, std::span<const std::int64_t> values);
  void put_integer(const std::string& name, std::int64_t value) {
    put(name, std::span<const std::int64_t>(&value, 1));
  }
  void put_text(const std::string& name, const std::string& text);

  /// The trailer, fsync, rename over `file`, fsync of the directory.
  void commit();
  /// Bytes written so far.
  std::uint64_t bytes() const { return length_ + buffer_.size(); }

private:
  void record(const std::string& name, std::uint8_t kind, std::uint64_t count, const void* data,
              std::size_t bytes);
  void append(const void* data, std::size_t n);
  void flush();
  [[noreturn]] void fail(const char* what);

  std::filesystem::path file_, tmp_;
  int fd_ = -1;
  bool committed_ = false;
  std::vector<unsigned char> buffer_;
  std::uint64_t length_ = 0; ///< bytes flushed to the file
  unsigned long crc_ = 0;    ///< zlib CRC-32 of the flushed bytes
};

/// A checkpoint read back whole and checked.
class CheckpointReader {
public:
  /// Reads and checks `file`. On a missing, truncated or corrupt file returns nullopt and says
  /// why in `why`.
  static std::optional<CheckpointReader> open(const std::filesystem::path& file, std::string& why);

  bool has(const std::string& name) const { return entries_.contains(name); }
  /// The named array; throws std::runtime_error if it is missing or of another kind.
  std::vector<double> doubles(const std::string& name) const;
  std::vector<std::int64_t> integers(const std::string& name) const;
  std::int64_t integer(const std::string& name) const;
  std::string text(const std::string& name) const;
  const std::filesystem::path& file() const { return file_; }

private:
  struct Entry {
    std::uint8_t kind = 0;
    std::uint64_t count = 0;
    std::size_t offset = 0; ///< into bytes_
  };
  const Entry& entry(const std::string& name, std::uint8_t kind) const;
  std::filesystem::path file_;
  std::vector<unsigned char> bytes_;
  std::map<std::string, Entry> entries_;
};

/// The checkpoints in `dir` (checkpoint_<step>.tck), newest (highest step) first.
std::vector<std::filesystem::path> list_checkpoints(const std::filesystem::path& dir);

/// The file name of the checkpoint after `step` steps.
std::string checkpoint_name(Index step);

} // namespace talus

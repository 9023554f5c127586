#pragma once
// The checkpoint container: named arrays of doubles, 64-bit integers or text, written
// atomically (a temporary file, flushed to disk, renamed over the name) and closed by a trailer
// with the payload's length and CRC-32, so a truncated or corrupt file is recognised and never
// half-read. The bytes are little-endian as the machine writes them; the layout is in
// docs/output-format.md ("Checkpoints"). What a run stores in it: solver/checkpoint.hpp.
#include "talus/core/types.hpp"

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace talus {

/// A checkpoint being assembled in memory; write() puts it on disk in one go.
class CheckpointWriter {
public:
  void put(const std::string& name, std::span<const double> values);
  void put(const std::string& name, std::span<const std::int64_t> values);
  void put(const std::string& name, double value) { put(name, std::span<const double>(&value, 1)); }
  void put_integer(const std::string& name, std::int64_t value) {
    put(name, std::span<const std::int64_t>(&value, 1));
  }
  void put_text(const std::string& name, const std::string& text);

  /// Writes `file` atomically: `file`.tmp, fsync, rename, fsync of the directory. Throws
  /// std::runtime_error naming the file and the system's reason (a full disk, say); the file
  /// that was there before is then untouched and the temporary removed.
  void write(const std::filesystem::path& file) const;
  std::size_t bytes() const { return payload_.size(); }

private:
  void record(const std::string& name, std::uint8_t kind, std::uint64_t count, const void* data,
              std::size_t bytes);
  std::vector<unsigned char> payload_;
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
  double number(const std::string& name) const;
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

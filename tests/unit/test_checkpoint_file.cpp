// The checkpoint container (io/checkpoint_file.hpp) and the case comparison of a resume
// (io/case_reader.hpp, case_differences).
#include "talus/io/case_reader.hpp"
#include "talus/io/checkpoint_file.hpp"

#include "temporary_directory.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

namespace fs = std::filesystem;

namespace {

class CheckpointFile : public talus::test_support::TemporaryDirectoryTest {
protected:
  /// A small checkpoint with every kind of entry, written to `file`.
  fs::path write_sample() {
    const fs::path file = root_ / "sample.tck";
    talus::CheckpointWriter w(file);
    const std::vector<double> numbers = {1.5, -0.0, std::numeric_limits<double>::denorm_min(),
                                         std::nan("7"), 1e308};
    w.put("numbers", numbers);
    w.put_integer("count", -42);
    w.put_text("text", std::string("a\0b", 3) + "é");
    w.put("empty", std::vector<double>{});
    w.commit();
    return file;
  }
  static std::string bytes_of(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }
  static void write_bytes(const fs::path& file, const std::string& bytes) {
    std::ofstream(file, std::ios::binary) << bytes;
  }
};

// What is written is read back bit for bit, NaN payloads and signed zeros included.
TEST_F(CheckpointFile, RoundTripsEveryKindBitwise) {
  const fs::path file = write_sample();
  EXPECT_FALSE(fs::exists(file.string() + ".tmp"));
  std::string why;
  const auto r = talus::CheckpointReader::open(file, why);
  ASSERT_TRUE(r) << why;
  const auto numbers = r->doubles("numbers");
  ASSERT_EQ(numbers.size(), 5u);
  EXPECT_EQ(numbers[0], 1.5);
  EXPECT_TRUE(std::signbit(numbers[1]));
  EXPECT_EQ(numbers[2], std::numeric_limits<double>::denorm_min());
  EXPECT_TRUE(std::isnan(numbers[3]));
  EXPECT_EQ(r->integer("count"), -42);
  EXPECT_EQ(r->text("text"), std::string("a\0b", 3) + "é");
  EXPECT_TRUE(r->doubles("empty").empty());
  EXPECT_FALSE(r->has("missing"));
  EXPECT_THROW(r->doubles("missing"), std::runtime_error);
  EXPECT_THROW(r->integers("numbers"), std::runtime_error); // another kind
}

// Every truncation and every single flipped bit is recognised: a resume never reads a damaged
// checkpoint.
TEST_F(CheckpointFile, EveryTruncationAndEveryFlippedBitIsRecognised) {
  const fs::path file = write_sample();
  const std::string good = bytes_of(file);
  const fs::path bad = root_ / "bad.tck";
  std::string why;
  for (std::size_t n = 0; n < good.size(); ++n) {
    write_bytes(bad, good.substr(0, n));
    EXPECT_FALSE(talus::CheckpointReader::open(bad, why)) << "truncated to " << n << " bytes";
  }
  for (std::size_t i = 0; i < good.size(); ++i)
    for (int bit = 0; bit < 8; ++bit) {
      std::string flipped = good;
      flipped[i] = static_cast<char>(flipped[i] ^ (1 << bit));
      write_bytes(bad, flipped);
      EXPECT_FALSE(talus::CheckpointReader::open(bad, why)) << "byte " << i << " bit " << bit;
    }
  write_bytes(bad, good + "x");
  EXPECT_FALSE(talus::CheckpointReader::open(bad, why)) << "a byte appended";
  EXPECT_FALSE(talus::CheckpointReader::open(root_ / "absent.tck", why));
}

// A write that fails (here: its temporary file cannot be created) throws, and one abandoned
// before commit() leaves nothing behind: the file that was there before is untouched.
TEST_F(CheckpointFile, AFailedWriteLeavesTheEarlierFile) {
  const fs::path file = write_sample();
  const std::string before = bytes_of(file);
  fs::create_directory(file.string() + ".tmp");
  EXPECT_THROW(talus::CheckpointWriter{file}, std::runtime_error);
  EXPECT_EQ(bytes_of(file), before);
  fs::remove(file.string() + ".tmp");
  {
    talus::CheckpointWriter abandoned(file); // destroyed without commit()
    abandoned.put_integer("x", 1);
  }
  EXPECT_EQ(bytes_of(file), before);
  EXPECT_FALSE(fs::exists(file.string() + ".tmp"));
}

TEST_F(CheckpointFile, CheckpointsAreListedNewestFirst) {
  for (const talus::Index step : {9, 100, 10}) {
    talus::CheckpointWriter w(root_ / talus::checkpoint_name(step));
    w.put_integer("x", 1);
    w.commit();
  }
  std::ofstream(root_ / "other.txt") << "x";
  const auto list = talus::list_checkpoints(root_);
  ASSERT_EQ(list.size(), 3u);
  EXPECT_EQ(list[0].filename(), talus::checkpoint_name(100));
  EXPECT_EQ(list[2].filename(), talus::checkpoint_name(9));
}

// The keys where two cases differ: values, keys only one has, list items; overrides applied;
// comments and layout no difference.
TEST(CaseDifferences, NameTheKeysThatDiffer) {
  const std::string a = "name: x   # a comment\ntime: {end_time: 1, dt: 0.1}\n"
                        "materials:\n  - {name: m, youngs_modulus: 1.0e6}\n";
  const std::string b = "name: x\ntime:\n  end_time: 1\n  dt: 0.1\n"
                        "materials:\n  - {name: m, youngs_modulus: 1.0e6}\n";
  EXPECT_TRUE(talus::case_differences(a, {}, b, {}).empty());
  EXPECT_EQ(talus::case_differences(a, {"time.end_time=2"}, b, {}),
            std::vector<std::string>{"time.end_time"});
  EXPECT_EQ(talus::case_differences(a, {"materials[0].youngs_modulus=2e6"}, b, {}),
            std::vector<std::string>{"materials[0].youngs_modulus"});
  EXPECT_EQ(talus::case_differences(a, {}, b + "gravity: [0, -9.81]\n", {}),
            std::vector<std::string>{"gravity"});
  // The same override on both sides is no difference.
  EXPECT_TRUE(talus::case_differences(a, {"time.dt=0.2"}, b, {"time.dt=0.2"}).empty());
}

} // namespace

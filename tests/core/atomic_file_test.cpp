// Output files and folders: complete or not at all, nothing of ours left behind, and stale
// temporaries of killed runs removed by the next run (sets/core/atomic_file.hpp).

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "sets/core/atomic_file.hpp"
#include "sets/core/error.hpp"

namespace fs = std::filesystem;

namespace {

struct ScratchFolder {
  fs::path path = fs::temp_directory_path() / ("sets-atomic-test-" + std::to_string(::getpid()));
  ScratchFolder() {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~ScratchFolder() { fs::remove_all(path); }
  // Names in the folder, sorted, one per line.
  std::string listing() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(path)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    std::string s;
    for (const auto& n : names) s += n + "\n";
    return s;
  }
};

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The id of a process that has ended (so no live process can own a temporary named after it,
// short of the id being reused at once).
pid_t ended_process() {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ::waitpid(child, nullptr, 0);
  return child;
}

}  // namespace

TEST(AtomicFile, WritesAndReplacesWithoutLeavingTemporaries) {
  ScratchFolder s;
  const fs::path f = s.path / "out.json";
  sets::write_file_atomically(f.string(), "first\n");
  sets::write_file_atomically(f.string(), "second\n");
  EXPECT_EQ(read(f), "second\n");
  EXPECT_EQ(s.listing(), "out.json\n");
}

TEST(AtomicFile, MissingFolderIsAnInputErrorNamingThePath) {
  ScratchFolder s;
  const fs::path f = s.path / "no" / "out.json";
  try {
    sets::write_file_atomically(f.string(), "x");
    FAIL() << "no error";
  } catch (const sets::InputError& e) {
    EXPECT_NE(std::string(e.what()).find(f.string()), std::string::npos) << e.what();
  }
  EXPECT_EQ(s.listing(), "");
}

TEST(AtomicFile, StaleTemporaryOfAKilledRunIsRemovedByTheNextRun) {
  ScratchFolder s;
  const std::string dead = ".out.json.sets-tmp." + std::to_string(ended_process()) + "-0";
  const std::string alive = ".out.json.sets-tmp." + std::to_string(::getppid()) + "-0";
  fs::create_directory(s.path / dead);
  std::ofstream(s.path / dead / "half.png") << "x";
  std::ofstream(s.path / alive) << "another run, still writing";
  std::ofstream(s.path / ".other.json.sets-tmp.1-0") << "not a temporary of this target";
  sets::write_file_atomically((s.path / "out.json").string(), "done\n");
  EXPECT_EQ(s.listing(), ".other.json.sets-tmp.1-0\n" + alive + "\nout.json\n");
}

TEST(AtomicDirectory, WithoutCommitNothingIsLeft) {
  ScratchFolder s;
  {
    sets::AtomicDirectory d(s.path / "report");
    std::ofstream(d.staging() / "report.txt") << "half";
    EXPECT_TRUE(fs::exists(d.staging()));
  }
  EXPECT_EQ(s.listing(), "");
}

TEST(AtomicDirectory, CommitPutsTheFolderInPlaceAsAWhole) {
  ScratchFolder s;
  const fs::path target = s.path / "report";
  {
    sets::AtomicDirectory d(target);
    std::ofstream(d.staging() / "a.txt") << "1";
    std::ofstream(d.staging() / "b.txt") << "2";
    EXPECT_FALSE(fs::exists(target));  // nothing visible before the commit
    d.commit();
  }
  EXPECT_EQ(read(target / "a.txt"), "1");
  {
    sets::AtomicDirectory d(target);  // replaces the old folder: its files do not mix with the new ones
    std::ofstream(d.staging() / "c.txt") << "3";
    d.commit();
  }
  EXPECT_FALSE(fs::exists(target / "a.txt"));
  EXPECT_EQ(read(target / "c.txt"), "3");
  EXPECT_EQ(s.listing(), "report\n");
}

// A target written with trailing separators is the same folder, staged beside it, not inside it.
TEST(AtomicDirectory, TrailingSeparatorsNameTheSameFolder) {
  ScratchFolder s;
  sets::AtomicDirectory d(s.path / "report//");
  EXPECT_EQ(d.target(), s.path / "report");
  EXPECT_EQ(d.staging().parent_path(), fs::absolute(s.path));
  std::ofstream(d.staging() / "a.txt") << "1";
  d.commit();
  EXPECT_EQ(read(s.path / "report" / "a.txt"), "1");
  EXPECT_EQ(s.listing(), "report\n");
}

TEST(AtomicDirectory, TargetThatIsAFileIsRefused) {
  ScratchFolder s;
  std::ofstream(s.path / "report") << "a file";
  sets::AtomicDirectory d(s.path / "report");
  EXPECT_THROW(d.commit(), sets::InputError);
}

TEST(AtomicFile, PendingTemporariesAreRemovedOnRequest) {
  // What an app's SIGINT/SIGTERM handler does: nested files and folders in progress all go.
  ScratchFolder s;
  sets::AtomicDirectory d(s.path / "report");
  fs::create_directories(d.staging() / "sub" / "deeper");
  for (int i = 0; i < 300; ++i) std::ofstream(d.staging() / ("f" + std::to_string(i) + ".dat")) << i;
  std::ofstream(d.staging() / "sub" / "deeper" / "x") << "x";
  sets::remove_pending_temporaries();
  EXPECT_EQ(s.listing(), "");
}

#include "sets/core/atomic_file.hpp"

#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <fstream>

#include "sets/core/error.hpp"

namespace sets {

namespace fs = std::filesystem;

namespace {

// ---------------------------------------------------------------- registry of temporaries
// Fixed storage, no allocation: remove_pending_temporaries() runs inside a signal handler.
constexpr int kSlots = 64;
struct Slot {
  std::atomic<int> state{0};  // 0 free, 1 being filled, 2 live
  char path[4096];
};
Slot g_slots[kSlots];

int register_temporary(const fs::path& p) noexcept {
  const std::string s = p.string();
  if (s.size() >= sizeof(Slot::path)) return -1;
  for (int i = 0; i < kSlots; ++i) {
    int expected = 0;
    if (g_slots[i].state.compare_exchange_strong(expected, 1)) {
      std::memcpy(g_slots[i].path, s.c_str(), s.size() + 1);
      g_slots[i].state.store(2);
      return i;
    }
  }
  return -1;  // all slots busy: still removed by its destructor, not by a signal handler
}

void unregister_temporary(int slot) noexcept {
  if (slot >= 0) g_slots[slot].state.store(0);
}

// Removes `name` (relative to dirfd) and, if it is a folder, everything inside, with system calls
// only (async-signal-safe: no allocation, no opendir).
void remove_tree(int dirfd, const char* name, int depth) noexcept {
  if (::unlinkat(dirfd, name, 0) == 0 || errno == ENOENT) return;
  if (depth > 16) return;
  const int fd = ::openat(dirfd, name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return;
  struct Entry {  // linux_dirent64
    unsigned long long ino;
    long long off;
    unsigned short reclen;
    unsigned char type;
    char name[1];
  };
  alignas(8) char buf[2048];
  // Entries are removed while reading, so read again from the start until only . and .. remain.
  for (int pass = 0; pass < 1000; ++pass) {
    ::lseek(fd, 0, SEEK_SET);
    bool removed_any = false;
    for (;;) {
      const long n = ::syscall(SYS_getdents64, fd, buf, sizeof buf);
      if (n <= 0) break;
      for (long off = 0; off < n;) {
        const auto* e = reinterpret_cast<const Entry*>(buf + off);
        const bool dot = e->name[0] == '.' && (e->name[1] == 0 || (e->name[1] == '.' && e->name[2] == 0));
        if (!dot) {
          remove_tree(fd, e->name, depth + 1);
          removed_any = true;
        }
        off += e->reclen;
      }
    }
    if (!removed_any) break;
  }
  ::close(fd);
  ::unlinkat(dirfd, name, AT_REMOVEDIR);
}

// ".<name>.sets-tmp." : the prefix of every temporary of `target`.
std::string temporary_prefix(const fs::path& target) { return "." + target.filename().string() + ".sets-tmp."; }

// A temporary "<prefix><pid>-<n>" whose process no longer exists was left by a killed run.
void remove_stale_temporaries(const fs::path& folder, const std::string& prefix) {
  std::error_code ec;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.compare(0, prefix.size(), prefix) != 0) continue;
    const long pid = std::strtol(name.c_str() + prefix.size(), nullptr, 10);
    if (pid <= 0 || pid == ::getpid()) continue;
    if (::kill(static_cast<pid_t>(pid), 0) == -1 && errno == ESRCH) {
      std::error_code ignore;
      fs::remove_all(it->path(), ignore);
    }
  }
}

std::atomic<unsigned> g_counter{0};

}  // namespace

// ---------------------------------------------------------------- TemporarySibling

TemporarySibling::TemporarySibling(const fs::path& target) {
  fs::path folder = target.parent_path();
  if (folder.empty()) folder = ".";
  const std::string prefix = temporary_prefix(target);
  remove_stale_temporaries(folder, prefix);
  path_ = fs::absolute(folder) / (prefix + std::to_string(::getpid()) + "-" + std::to_string(g_counter++));
  slot_ = register_temporary(path_);
}

TemporarySibling::~TemporarySibling() {
  if (path_.empty()) return;
  std::error_code ec;
  fs::remove_all(path_, ec);
  unregister_temporary(slot_);
}

void TemporarySibling::release() noexcept {
  unregister_temporary(slot_);
  slot_ = -1;
  path_.clear();
}

void remove_pending_temporaries() noexcept {
  for (auto& slot : g_slots)
    if (slot.state.load() == 2) remove_tree(AT_FDCWD, slot.path, 0);
}

// ---------------------------------------------------------------- files

void write_file_atomically(const std::string& path, const std::string& text) {
  const fs::path target(path);
  TemporarySibling tmp(target);
  {
    std::ofstream out(tmp.path(), std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(path + ": cannot write (folder missing or not writable)");
    out << text;
    out.flush();
    if (!out) throw InputError(path + ": write failed");
  }
  std::error_code ec;
  fs::rename(tmp.path(), target, ec);
  if (ec) throw InputError(path + ": cannot rename the finished file into place (" + ec.message() + ")");
  tmp.release();
}

// ---------------------------------------------------------------- folders

namespace {

// "report/" names the folder "report": without its trailing separators (an empty file name would
// put the staging folder inside the target itself).
fs::path folder_named(fs::path p) {
  while (!p.has_filename() && p.has_relative_path()) p = p.parent_path();
  return p;
}

}  // namespace

AtomicDirectory::AtomicDirectory(const fs::path& target) : target_(folder_named(target)), staging_(target_) {
  std::error_code ec;
  if (!fs::create_directory(staging_.path(), ec) || ec)
    throw InputError(target.string() + ": cannot create the folder (parent folder missing or not writable)");
}

void AtomicDirectory::commit() {
  std::error_code ec;
  const auto status = fs::symlink_status(target_, ec);
  if (!fs::exists(status)) {
    fs::rename(staging_.path(), target_, ec);
    if (ec) throw InputError(target_.string() + ": cannot rename the finished folder into place (" + ec.message() + ")");
    staging_.release();
    return;
  }
  if (!fs::is_directory(status)) throw InputError(target_.string() + ": exists and is not a folder");
  // Exchange the two folders in one step, then remove the old one (now at the staging name).
  if (::renameat2(AT_FDCWD, staging_.path().c_str(), AT_FDCWD, target_.c_str(), RENAME_EXCHANGE) == 0) {
    fs::remove_all(staging_.path(), ec);
    staging_.release();
    return;
  }
  if (errno != EINVAL && errno != ENOSYS)
    throw InputError(target_.string() + ": cannot replace the folder (" + std::strerror(errno) + ")");
  // A file system without the exchange: move the old folder aside, the new one in, then remove the old.
  TemporarySibling old(target_);
  fs::rename(target_, old.path(), ec);
  if (ec) throw InputError(target_.string() + ": cannot replace the folder (" + ec.message() + ")");
  fs::rename(staging_.path(), target_, ec);
  if (ec) {
    std::error_code undo;
    fs::rename(old.path(), target_, undo);
    throw InputError(target_.string() + ": cannot rename the finished folder into place (" + ec.message() + ")");
  }
  staging_.release();
}

}  // namespace sets

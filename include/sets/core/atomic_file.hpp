#pragma once
// Output files and folders are written completely or not at all, and nothing of ours stays behind.
//
// Every temporary is a hidden sibling of its target, named ".<target>.sets-tmp.<pid>", so that
//  - the final rename stays on one file system (atomic);
//  - a temporary left by a run that was killed with SIGKILL is recognised by the next run writing
//    the same target (its process id no longer exists) and removed;
//  - an app's SIGINT/SIGTERM handler can remove the temporaries in progress with
//    remove_pending_temporaries(), which is async-signal-safe.

#include <filesystem>
#include <string>

namespace sets {

/// Writes `text` to `path` through a hidden temporary file in the same folder and renames it into
/// place, so a reader never sees a half-written file. Throws InputError naming the path.
void write_file_atomically(const std::string& path, const std::string& text);

/// A hidden temporary beside `target` (".<name>.sets-tmp.<pid>"), registered for removal by
/// remove_pending_temporaries() and removed by the destructor unless released. Creating one first
/// removes the stale temporaries of `target` whose process is gone.
class TemporarySibling {
 public:
  explicit TemporarySibling(const std::filesystem::path& target);
  ~TemporarySibling();
  TemporarySibling(const TemporarySibling&) = delete;
  TemporarySibling& operator=(const TemporarySibling&) = delete;

  const std::filesystem::path& path() const { return path_; }
  /// The temporary is gone (renamed into place): forget it.
  void release() noexcept;

 private:
  std::filesystem::path path_;
  int slot_ = -1;
};

/// A folder written as a whole: files go into staging(), a hidden folder beside the target;
/// commit() renames it into place (if the target exists, the two are exchanged atomically and the
/// old one removed). Without commit() the staging folder is removed. Throws InputError.
class AtomicDirectory {
 public:
  explicit AtomicDirectory(const std::filesystem::path& target);
  const std::filesystem::path& staging() const { return staging_.path(); }
  const std::filesystem::path& target() const { return target_; }
  void commit();

 private:
  std::filesystem::path target_;
  TemporarySibling staging_;
};

/// Removes every temporary currently in progress (files and folders, also nested ones).
/// Async-signal-safe: for a SIGINT/SIGTERM handler.
void remove_pending_temporaries() noexcept;

}  // namespace sets

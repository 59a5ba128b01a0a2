// Runs of a case in child processes of this program, each in its own folder keyed by its complete
// inputs: what `limit` and `campaign` run. A run is deterministic, so a finished run whose key is
// the key of a wanted one is read back instead of run again (an interrupted search or campaign
// resumes), and a run with any other input — another override, an edited case, another build of
// the program — never is.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace tc {

/// This program's build: 16 hex digits of the 64-bit FNV-1a hash of its executable's bytes (read
/// once). Another build may compute other numbers, so it is part of every run's key.
std::string program_identity();

/// The complete inputs of a run, as text: the program (program_identity), the case file (its
/// absolute path and its content, keys and values without comments: canonical_case_text), every
/// override in the order given (a later one wins, so the order is part of the key) and the
/// material library the case reads (`library`, Case::material_library; "" when it reads none),
/// likewise. Mesh files the case names are not in it.
std::string run_key(const std::string& case_path, const std::vector<std::string>& overrides,
                    const std::string& library);

/// A folder name for a run: `label` then 12 hex digits of its key's 64-bit FNV-1a hash, so runs
/// of different inputs never share a folder.
std::string run_folder_name(const std::string& label, const std::string& key);

struct ChildRun {
  std::string dir;                // run.key, run.log and the run's own output
  std::string key;                // run_key of its inputs
  std::vector<std::string> args;  // `run` and its options (after the program's path)
  int exit_code = -1;             // the child's exit status once run; -1 killed or not run
  /// Went on from a checkpoint its folder held (an interrupted run of the same key).
  bool restarted = false;
};

/// Finished with these inputs: DIR/summary.json is there and DIR/run.key holds `key`. A folder
/// that holds another key (a hash collision, or a folder written by hand) is an error naming it.
bool finished_run(const ChildRun& r);

/// The files a set of runs reads (the case, the material library) with their text when it
/// started (canonical_case_text, as in run_key): a file edited while the runs go on would have
/// the later runs read other inputs than their keys say.
class InputFiles {
 public:
  /// Holds `path` and its text now; "" and a path already held are ignored.
  void add(const std::string& path);
  /// The first file whose text is no longer the one held (or that cannot be read), or "".
  std::string changed() const;
  /// Throws InputsChanged naming the file when one has changed: before results are written.
  void require_unchanged() const;

 private:
  std::vector<std::pair<std::string, std::string>> files_;  // path, text
};

/// A set of runs stopped because one of its input files changed while they went on.
struct InputsChanged : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Runs `todo`, `jobs` at a time, each `this program ARGS` in its folder (created, run.key written
/// first, the run's output to run.log); `on_done` is called as each ends, in the order they end.
/// A folder that holds an interrupted run of the same key (run.key, no summary.json) and its
/// checkpoints (a case with output.checkpoint) goes on from the newest (`run --restart` in place
/// of `--out DIR --force`); a restart refused or failed there (exit 2) runs again from the start.
/// The children execute this process's own image (/proc/self/exe), so a program rebuilt at its path
/// meanwhile does not run under the key of the build that started them; they end (SIGKILL) when
/// this process ends, however it ends, so none outlives the lock on its folder. With `inputs`, the
/// files are checked first, before each start and at each end: once one has changed no run starts,
/// a run that ends after the change (it may have read the new text under the old key) has its
/// summary.json set aside as summary.json.stale (not reused: it runs again next time), and when the
/// runs under way have ended InputsChanged names the file.
void run_children(const std::vector<ChildRun*>& todo, int jobs,
                  const std::function<void(ChildRun&)>& on_done = {},
                  const InputFiles* inputs = nullptr);

/// Starts `argv` (argv[0] a path) with its output to `log` and waits: its exit status, or -1
/// when it could not start or was killed.
int run_program(const std::vector<std::string>& argv, const std::string& log);

/// Holds a runs folder for one search or campaign while it lives: an exclusive lock (flock) on
/// DIR/runs/.lock, which the system drops when the process ends however it ends, so a killed
/// campaign leaves nothing to clean up. Movable, not copyable.
class RunsFolderLock {
 public:
  RunsFolderLock() = default;
  explicit RunsFolderLock(const std::string& dir);
  RunsFolderLock(RunsFolderLock&& other) noexcept;
  RunsFolderLock& operator=(RunsFolderLock&& other) noexcept;
  RunsFolderLock(const RunsFolderLock&) = delete;
  RunsFolderLock& operator=(const RunsFolderLock&) = delete;
  ~RunsFolderLock();

 private:
  int fd_ = -1;
};

/// Makes DIR ready for a search's or campaign's runs and locks it: a folder that holds earlier
/// runs (DIR/runs) is kept as it is, to be resumed; any other non-empty folder is refused, and so
/// is a folder another live search or campaign holds (OutputError, naming its process), so that
/// two never write the same runs and results.
RunsFolderLock prepare_runs_folder(const std::string& dir);

}  // namespace tc

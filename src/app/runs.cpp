// Runs of a case in child processes, keyed by their inputs (runs.hpp).
#include "tetcontact/app/runs.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "tetcontact/io/case.hpp"
#include "tetcontact/io/checkpoint.hpp"
#include "tetcontact/io/files.hpp"

namespace tc {

namespace fs = std::filesystem;

namespace {}  // namespace

std::string program_identity() {
  static const std::string id = [] {
    // The running image itself (the path's file may have been rebuilt since it started).
    std::ifstream in("/proc/self/exe", std::ios::binary);
    if (!in) throw std::runtime_error("/proc/self/exe: cannot read this program to key its runs");
    Fnv1a f;
    std::vector<char> buf(1 << 16);
    while (in.read(buf.data(), static_cast<std::streamsize>(buf.size())) || in.gcount() > 0)
      f.add(buf.data(), static_cast<std::size_t>(in.gcount()));
    return f.hex();
  }();
  return id;
}

std::string run_key(const std::string& case_path, const std::vector<std::string>& overrides,
                    const std::string& library) {
  std::ostringstream key;
  key << "program " << program_identity() << "\n";
  key << "case " << fs::absolute(case_path).lexically_normal().string() << "\n";
  for (const std::string& o : overrides) key << "set " << o << "\n";
  key << "text\n" << canonical_case_text(case_path) << "\n";
  if (!library.empty()) key << "library\n" << canonical_case_text(library) << "\n";
  return key.str();
}

std::string run_folder_name(const std::string& label, const std::string& key) {
  Fnv1a f;
  f.add(key.data(), key.size());
  return label + "_" + f.hex().substr(0, 12);
}

namespace {

// The key a run folder holds (run.key), "" when it holds none.
std::string stored_key(const std::string& dir) {
  std::ifstream in(dir + "/run.key", std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

bool finished_run(const ChildRun& r) {
  if (!fs::exists(r.dir + "/summary.json")) return false;
  if (stored_key(r.dir) != r.key)
    throw std::runtime_error(r.dir +
                             ": holds a finished run of other inputs than its name says "
                             "(run.key differs); move the folder away");
  return true;
}

namespace {

// Forks and execs `program` (a path, or a name looked up in PATH) with the arguments `args`
// (args[0] its name) and its output to `log` and no input: the child's pid, or -1. The child
// ends (SIGKILL: a run with checkpoints would finish its step on SIGTERM) when this process does,
// however it ends: a run left going without the search
// or campaign that holds its folder would race a new one started on the same folder.
pid_t start_program(const std::string& program, std::vector<std::string> args,
                    const std::string& log) {
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid == 0) {  // the child: its output to the log, then the program
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(127);  // the parent ended before the line above
    const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int in = open("/dev/null", O_RDONLY);
    if (fd >= 0) dup2(fd, 1), dup2(fd, 2);
    if (in >= 0) dup2(in, 0);
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    execvp(program.c_str(), argv.data());
    _exit(127);
  }
  return pid;
}

}  // namespace

int run_program(const std::vector<std::string>& argv, const std::string& log) {
  const pid_t pid = start_program(argv.at(0), argv, log);
  if (pid < 0) return -1;
  int status = 0;
  if (waitpid(pid, &status, 0) != pid) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

void InputFiles::add(const std::string& path) {
  if (path.empty()) return;
  for (const auto& f : files_)
    if (f.first == path) return;
  files_.emplace_back(path, canonical_case_text(path));
}

std::string InputFiles::changed() const {
  for (const auto& [path, text] : files_) {
    try {
      if (canonical_case_text(path) != text) return path;
    } catch (const std::exception&) {
      return path;  // unreadable now, or no longer valid YAML
    }
  }
  return "";
}

namespace {

std::string changed_message(const std::string& path) {
  return path + ": changed while its runs went on (each run is keyed by the text it had when " +
         "they started)";
}

}  // namespace

void InputFiles::require_unchanged() const {
  if (const std::string path = changed(); !path.empty())
    throw InputsChanged(changed_message(path) + "; nothing written: start again to run with " +
                        "the new text");
}

void run_children(const std::vector<ChildRun*>& runs, int jobs,
                  const std::function<void(ChildRun&)>& on_done, const InputFiles* inputs) {
  std::vector<ChildRun*> todo = runs;  // and the restarts refused, again from the start
  // The children run this very image (a forked child's /proc/self/exe is its parent's), not
  // whatever file now lies at its path, so that their runs are of the build in their key.
  // Named `tetcontact` (argv[0]), as `ps` and `top` show them.
  const std::string exe = "/proc/self/exe";
  std::map<pid_t, ChildRun*> running;
  std::size_t next = 0;
  std::string changed;  // the input file found edited: nothing more starts
  std::size_t set_aside = 0;
  const auto check = [&] {
    if (changed.empty() && inputs) changed = inputs->changed();
    return changed.empty();
  };
  // An interrupted run of this key with checkpoints: `run --restart DIR` instead of `--out DIR
  // --force`.
  const auto resumable = [](const ChildRun& r) {
    return !fs::exists(r.dir + "/summary.json") && stored_key(r.dir) == r.key &&
           !checkpoint_files(r.dir).empty();
  };
  const auto restart_args = [](const ChildRun& r) {
    std::vector<std::string> args;
    for (std::size_t k = 0; k < r.args.size(); ++k) {
      if (r.args[k] == "--out") {
        ++k;
        continue;
      }
      if (r.args[k] != "--force") args.push_back(r.args[k]);
    }
    args.insert(args.end(), {"--restart", r.dir});
    return args;
  };
  check();  // also when nothing is left to run: its results would be read under the old text
  while ((next < todo.size() && changed.empty()) || !running.empty()) {
    while (next < todo.size() && static_cast<int>(running.size()) < std::max(1, jobs) && check()) {
      ChildRun* r = todo[next++];
      fs::create_directories(r->dir);
      r->restarted = !r->restarted && resumable(*r);
      if (r->restarted) {  // the interrupted run's log kept beside the restart's
        std::error_code ec;
        fs::rename(r->dir + "/run.log", r->dir + "/interrupted.log", ec);
      }
      write_file_atomic(r->dir + "/run.key", r->key);
      std::vector<std::string> args{"tetcontact"};
      const std::vector<std::string> own = r->restarted ? restart_args(*r) : r->args;
      args.insert(args.end(), own.begin(), own.end());
      const pid_t pid = start_program(exe, args, r->dir + "/run.log");
      if (pid < 0) throw std::runtime_error("cannot start a run (fork)");
      running[pid] = r;
    }
    if (running.empty()) break;  // stopped by a change before anything more started
    int status = 0;
    const pid_t done = waitpid(-1, &status, 0);
    if (done < 0) {
      if (errno == EINTR) continue;
      break;
    }
    const auto it = running.find(done);
    if (it == running.end()) continue;
    ChildRun* r = it->second;
    running.erase(it);
    r->exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    if (r->restarted && r->exit_code == 2) {  // the checkpoint refused: from the start
      std::error_code ec;
      fs::rename(r->dir + "/run.log", r->dir + "/restart.log", ec);
      fs::remove_all(checkpoint_folder(r->dir), ec);
      todo.push_back(r);
      continue;
    }
    if (!check()) {  // it may have read the new text: not a run of its key
      std::error_code ec;
      if (fs::exists(r->dir + "/summary.json"))
        fs::rename(r->dir + "/summary.json", r->dir + "/summary.json.stale", ec);
      ++set_aside;
      continue;
    }
    if (on_done) on_done(*r);
  }
  if (!changed.empty())
    throw InputsChanged(
        changed_message(changed) + "; " + std::to_string(set_aside) +
        " run(s) that ended after the change set aside (summary.json.stale), the ones before it " +
        "kept; start again to run the rest with the new text");
}

RunsFolderLock::RunsFolderLock(const std::string& dir) {
  const std::string path = dir + "/runs/.lock";
  fd_ = open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw OutputError(path + ": cannot open the folder's lock");
  if (flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    char pid[32] = {};
    const ssize_t n = pread(fd_, pid, sizeof pid - 1, 0);
    close(fd_);
    fd_ = -1;
    throw OutputError(dir + ": another search or campaign is running in this folder (process " +
                      std::string(pid, n > 0 ? static_cast<std::size_t>(n) : 0) +
                      ", runs/.lock); wait for it to end, or choose another --out");
  }
  // The pid first, then the length: a reader never finds the file empty.
  const std::string me = std::to_string(getpid());
  if (pwrite(fd_, me.data(), me.size(), 0) != static_cast<ssize_t>(me.size()) ||
      ftruncate(fd_, static_cast<off_t>(me.size())) != 0) {
    close(fd_);
    fd_ = -1;
    throw OutputError(path + ": cannot write the folder's lock");
  }
}

RunsFolderLock::RunsFolderLock(RunsFolderLock&& other) noexcept : fd_(other.fd_) {
  other.fd_ = -1;
}

RunsFolderLock& RunsFolderLock::operator=(RunsFolderLock&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) close(fd_);
    fd_ = other.fd_;
    other.fd_ = -1;
  }
  return *this;
}

RunsFolderLock::~RunsFolderLock() {
  if (fd_ >= 0) close(fd_);  // closing the last descriptor drops the lock
}

RunsFolderLock prepare_runs_folder(const std::string& dir) {
  if (!fs::exists(dir + "/runs")) {
    prepare_output_dir(dir, false);
    std::error_code ec;
    fs::create_directories(dir + "/runs", ec);
    if (ec) throw OutputError(dir + "/runs: cannot create it: " + ec.message());
  }
  return RunsFolderLock(dir);
}

}  // namespace tc

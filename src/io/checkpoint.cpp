#include "tetcontact/io/checkpoint.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "tetcontact/io/files.hpp"

namespace tc {
namespace fs = std::filesystem;

namespace {

constexpr const char* k_magic = "tetcontact checkpoint 1";

std::string hash_of(const std::string& bytes) {
  Fnv1a f;
  f.add(bytes.data(), bytes.size());
  return f.hex();
}

bool is_checkpoint_file(const fs::path& p) {
  const std::string name = p.filename().string();
  return name.rfind("step_", 0) == 0 && p.extension() == ".ckpt";
}

}  // namespace

std::string checkpoint_folder(const std::string& run_dir) {
  return run_dir + "/checkpoints";
}

std::vector<std::string> checkpoint_files(const std::string& run_dir) {
  std::vector<std::string> files;
  std::error_code ec;
  const std::string folder = checkpoint_folder(run_dir);
  if (!fs::is_directory(folder, ec)) return files;
  for (const auto& e : fs::directory_iterator(folder, ec))
    if (e.is_regular_file() && is_checkpoint_file(e.path())) files.push_back(e.path().string());
  std::sort(files.begin(), files.end());  // step_ and ten digits: by step
  return files;
}

std::string write_checkpoint(const std::string& run_dir, const CheckpointHeader& h,
                             const std::string& payload, int keep) {
  const std::string folder = checkpoint_folder(run_dir);
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec) throw OutputError(folder + ": cannot create: " + ec.message());
  char name[40];
  std::snprintf(name, sizeof name, "/step_%010ld.ckpt", h.step);
  std::ostringstream head;
  char t[40];
  std::snprintf(t, sizeof t, "%a", h.t);
  head << k_magic << "\nprogram " << h.program << "\ninputs " << h.inputs << "\nstep " << h.step
       << "\nt " << t << "\npayload " << payload.size() << ' ' << hash_of(payload) << "\n";
  const std::string path = folder + name;
  // Written under a temporary name, flushed to the disk, renamed, the folder flushed: after a
  // crash of the machine the file is whole or absent, and only then are older ones removed.
  const std::string tmp = path + ".tmp", bytes = head.str() + payload;
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw OutputError(tmp + ": cannot open for writing: " + std::strerror(errno));
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const std::string why = std::strerror(errno);
      ::close(fd);
      fs::remove(tmp, ec);
      throw OutputError(tmp + ": write failed: " + why);
    }
    done += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0 || ::close(fd) != 0) {
    fs::remove(tmp, ec);
    throw OutputError(tmp + ": cannot be flushed to the disk");
  }
  fs::rename(tmp, path, ec);
  if (ec) throw OutputError(path + ": cannot rename into place: " + ec.message());
  if (const int dfd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
  std::vector<std::string> files = checkpoint_files(run_dir);
  for (std::size_t k = 0; k + static_cast<std::size_t>(keep) < files.size(); ++k)
    fs::remove(files[k], ec);
  return path;
}

std::string restart_run_folder(const std::string& where) {
  fs::path p = fs::path(where).lexically_normal();
  if (p.filename().empty()) p = p.parent_path();  // a trailing slash
  if (is_checkpoint_file(p)) p = p.parent_path();
  if (p.filename() == "checkpoints") p = p.parent_path();
  return p.empty() ? std::string(".") : p.string();
}

namespace {

// A checkpoint file that is not whole (cut short, its checksum wrong, not this format).
struct DamagedCheckpoint : CheckpointError {
  using CheckpointError::CheckpointError;
};

Checkpoint parse_checkpoint(const std::string& path) {
  Checkpoint c;
  c.path = path;
  std::ifstream in(c.path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in) throw CheckpointError(c.path + ": cannot read");
  const std::string bytes = text.str();
  // The header: six lines, then the payload.
  std::istringstream head(bytes);
  std::string magic, key, t_hex, payload_hash;
  std::size_t payload_size = 0;
  std::getline(head, magic);
  if (magic != k_magic)
    throw DamagedCheckpoint(c.path +
                            ": not a checkpoint of this program's format (its first line is '" +
                            magic.substr(0, 60) + "', expected '" + k_magic + "')");
  head >> key >> c.header.program >> key >> c.header.inputs >> key >> c.header.step >> key >>
      t_hex >> key >> payload_size >> payload_hash;
  head.ignore(1);
  if (!head) throw DamagedCheckpoint(c.path + ": damaged header");
  c.header.t = std::strtod(t_hex.c_str(), nullptr);
  const std::size_t start = static_cast<std::size_t>(head.tellg());
  if (bytes.size() - start != payload_size)
    throw DamagedCheckpoint(c.path + ": damaged: " + std::to_string(bytes.size() - start) +
                            " bytes of data where the header says " + std::to_string(payload_size));
  c.payload = bytes.substr(start);
  if (hash_of(c.payload) != payload_hash)
    throw DamagedCheckpoint(c.path + ": damaged: its data does not match its checksum");
  return c;
}

}  // namespace

Checkpoint read_checkpoint(const std::string& where, const std::string& program,
                           const std::string& inputs, std::vector<std::string>* skipped) {
  std::vector<std::string> files;
  std::error_code ec;
  const bool one_file = fs::is_regular_file(where, ec);
  if (one_file) {
    files.push_back(where);
  } else {
    files = checkpoint_files(restart_run_folder(where));
    if (files.empty())
      throw CheckpointError(where + ": no checkpoint to restart from (a run writes them into " +
                            checkpoint_folder(restart_run_folder(where)) +
                            " when its case sets output.checkpoint)");
  }
  // The newest that is whole; a damaged one (a crash while the disk had not written it) gives
  // way to the one before, said in `skipped`. Named as one file, it must be whole.
  Checkpoint c;
  for (std::size_t k = files.size(); k-- > 0;) {
    try {
      c = parse_checkpoint(files[k]);
      break;
    } catch (const DamagedCheckpoint& e) {
      if (one_file || k == 0) throw;
      if (skipped) skipped->push_back(e.what());
    }
  }
  if (c.header.program != program)
    throw CheckpointError(c.path + ": written by another build of tetcontact (program " +
                          c.header.program + ", this one is " + program +
                          "): another build may compute other numbers, so it cannot go on from "
                          "it; run the case anew");
  if (c.header.inputs != inputs)
    throw CheckpointError(c.path + ": written for other inputs (inputs " + c.header.inputs +
                          ", these are " + inputs +
                          "): the case file's content, an override (--set) or the material "
                          "library differ from the run that wrote it");
  return c;
}

}  // namespace tc

#pragma once
// A test that starts the granstack program as a user would (from argument vectors, never a
// shell, so odd paths reach it untouched), each test in a fresh directory of its own, with the
// helpers the safety and reliability tests share.
#include "scratch.hpp"

#include <granstack/os/process.hpp>

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <thread>
#include <sys/mount.h>
#include <unistd.h>
#include <vector>

namespace granstack::test {

namespace fs = std::filesystem;

struct Result {
  int code = -1;
  int signal = 0;
  std::string output;  // stdout and stderr
};

inline std::string read_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

class GranstackTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = scratch(fs::path(GRANSTACK_TEST_WORKDIR) / (std::string(info->test_suite_name()) + "_" + info->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  fs::path path(const std::string& name) const { return dir_ / name; }

  // Starts granstack with these arguments in `cwd` (the test's directory by default).
  os::Child start(const std::vector<std::string>& args, const fs::path& cwd = {}) {
    // GRANSTACK_TEST_EXE runs these tests against another build (e.g. an older commit's).
    const char* other = std::getenv("GRANSTACK_TEST_EXE");
    std::vector<std::string> argv{other != nullptr ? other : GRANSTACK_EXE};
    argv.insert(argv.end(), args.begin(), args.end());
    os::StartOptions o;
    o.cwd = cwd.empty() ? dir_ : cwd;
    o.output = dir_ / fmt_log(++runs_);
    o.extra_environment = environment_;
    const auto child = os::start(argv, o);
    logs_[child.pid] = o.output;
    return child;
  }
  // Waits for a started granstack at most `seconds` (then kills it: the test fails).
  Result finish(const os::Child& child, double seconds = 240) {
    Result r;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    for (;;) {
      if (const auto end = os::poll(child)) {
        r.code = end->code;
        r.signal = end->signal;
        break;
      }
      if (std::chrono::steady_clock::now() > deadline) {
        os::kill_group(child);
        os::wait(child);
        ADD_FAILURE() << "granstack did not end within " << seconds << " s";
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    r.output = read_bytes(logs_[child.pid]);
    return r;
  }
  Result granstack(const std::vector<std::string>& args, const fs::path& cwd = {}, double seconds = 240) {
    return finish(start(args, cwd), seconds);
  }

#ifdef GRANSTACK_SOURCE_DIR
  // The tests' design space (tests/data/design/small_space.toml) written as `name` in the test's
  // directory; its text.
  std::string small_space(const std::string& name = "small.toml") {
    const auto text = read_bytes(fs::path(GRANSTACK_SOURCE_DIR) / "tests" / "data" / "design" / "small_space.toml");
    std::ofstream(path(name)) << text;
    return text;
  }
#endif

  // `granstack generate -o NAME FLAGS...`, then the case run on refsim; both must succeed.
  void generate_and_run(const std::string& name, const std::vector<std::string>& flags) {
    std::vector<std::string> args{"generate", "-o", name};
    args.insert(args.end(), flags.begin(), flags.end());
    auto r = granstack(args);
    ASSERT_EQ(r.code, 0) << r.output;
    r = granstack({"run", "--engine", "refsim", name});
    ASSERT_EQ(r.code, 0) << r.output;
  }

  fs::path dir_;
  std::vector<std::string> environment_;  // NAME=VALUE added for every granstack the test starts
  int runs_ = 0;
  std::map<pid_t, fs::path> logs_;  // each started granstack's output

 private:
  static std::string fmt_log(int n) { return ".granstack-" + std::to_string(n) + ".out"; }
};

inline void expect_contains(const Result& r, const std::string& words) {
  EXPECT_NE(r.output.find(words), std::string::npos) << "missing '" << words << "' in:\n" << r.output;
}

// Processes (other than this test) whose working directory lies in `dir`: LIGGGHTS left behind.
inline std::vector<std::string> processes_in(const fs::path& dir) {
  std::vector<std::string> found;
  const auto root = fs::weakly_canonical(dir).string();
  for (const auto& p : fs::directory_iterator("/proc")) {
    const auto name = p.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos || std::stoi(name) == ::getpid()) continue;
    std::error_code ec;
    const auto cwd = fs::read_symlink(p.path() / "cwd", ec).string();
    if (!ec && cwd.rfind(root, 0) == 0) found.push_back(name + " " + read_bytes(p.path() / "comm"));
  }
  return found;
}

// Waits until `pred` holds (at most `seconds`).
template <typename Pred>
bool eventually(Pred pred, double seconds) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (!pred()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return true;
}

// A small file system to fill (a tmpfs of `size`, e.g. "2m") mounted at `dir` for one test and
// unmounted after it; mounted() is false where that needs what the test does not have (root,
// mount(2)): the test then says skipped.
class SmallDisk {
 public:
  SmallDisk(const fs::path& dir, const std::string& size) : dir_(dir) {
    fs::create_directories(dir);
    mounted_ = ::geteuid() == 0 && ::mount("tmpfs", dir.c_str(), "tmpfs", 0, ("size=" + size).c_str()) == 0;
  }
  ~SmallDisk() {
    if (mounted_) ::umount2(dir_.c_str(), MNT_DETACH);
  }
  SmallDisk(const SmallDisk&) = delete;
  SmallDisk& operator=(const SmallDisk&) = delete;
  bool mounted() const { return mounted_; }

 private:
  fs::path dir_;
  bool mounted_ = false;
};

inline std::string status_of(const fs::path& case_dir) {
  const auto text = read_bytes(case_dir / "run.json");
  const auto at = text.find("\"status\": \"");
  return at == std::string::npos ? "" : text.substr(at + 11, text.find('"', at + 11) - at - 11);
}

}  // namespace granstack::test

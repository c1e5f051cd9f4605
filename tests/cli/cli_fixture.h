// The CliTest fixture: runs the real `illum` binary in a fresh temporary folder and checks
// the bad-input contract (exit code 2, one stderr line naming the problem, no output file).
// Shared by every test file in tests/cli.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace fs = std::filesystem;

namespace illum_cli_test {

struct Result {
  int exit_code = -1;
  std::string out, err;
  int err_lines() const {
    int n = 0;
    for (char c : err) n += c == '\n';
    return n;
  }
};

inline std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

class CliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("illum-cli-" + std::to_string(::getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // The command built by appending: GCC 12 reports a false -Warray-bounds on a chain of
  // operator+ as inlined into some tests.
  Result run(const std::string& args) {
    std::string command = ILLUM_BINARY_DIR;
    command += "/bin/illum ";
    command += args;
    return run_command(command);
  }
  // Any shell command line, its stdout and stderr captured in the test folder.
  Result run_command(const std::string& command) {
    const fs::path out = dir_ / "stdout.txt", err = dir_ / "stderr.txt";
    const std::string cmd = command + " >" + out.string() + " 2>" + err.string() + " </dev/null";
    const int status = std::system(cmd.c_str());
    Result r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.out = slurp(out);
    r.err = slurp(err);
    return r;
  }
  // Starts `command` under /bin/sh -c without waiting ("exec ..." makes the pid the
  // command's own, so signals reach it rather than the shell).
  static pid_t start_command(const std::string& command) {
    const pid_t pid = fork();
    if (pid == 0) {
      execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
      _exit(127);
    }
    return pid;
  }
  // Waits up to `limit` for `pid` to end and stores its wait status; past the limit kills it
  // (SIGCONT, then SIGKILL) and returns false.
  static bool wait_for(pid_t pid, std::chrono::milliseconds limit, int* status) {
    const auto start = std::chrono::steady_clock::now();
    while (waitpid(pid, status, WNOHANG) == 0) {
      if (std::chrono::steady_clock::now() - start > limit) {
        kill(pid, SIGCONT);
        kill(pid, SIGKILL);
        waitpid(pid, status, 0);
        return false;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return true;
  }
  // start_command, `signal` after `delay`, wait_for: the fork–signal–wait of the tests that
  // stop a running command. False when it did not end within `limit` of the signal.
  static bool signal_and_wait(const std::string& command, std::chrono::milliseconds delay,
                              int signal, std::chrono::milliseconds limit, int* status) {
    const pid_t pid = start_command(command);
    if (pid < 0) return false;
    std::this_thread::sleep_for(delay);
    kill(pid, signal);
    return wait_for(pid, limit, status);
  }
  fs::path write(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / name;
    std::ofstream(p) << text;
    return p;
  }
  // The Cornell box as a scene file of its own, its mesh under `transform` (JSON).
  std::string cornell_copy(const std::string& name, const std::string& transform) {
    const std::string obj = std::string(ILLUM_DATA_DIR) + "/scenes/cornell/cornell_box.obj";
    return write(name + ".illum.json",
                 "{\"meshes\": [{\"file\": \"" + obj + "\", \"scale\": 0.001" +
                     (transform.empty() ? "" : ", \"transform\": " + transform) + "}]}")
        .string();
  }
  // A unit quad in the xy plane (quad.bin: 4 positions, 6 indices) and the glTF scene
  // `name`.gltf whose `nodes` (each a JSON object) place `meshes` meshes, each that quad.
  std::string quad_gltf(const std::string& name, const std::vector<std::string>& nodes,
                        int meshes = 1) {
    const float positions[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    const uint16_t indices[6] = {0, 1, 2, 0, 2, 3};
    std::string bin(reinterpret_cast<const char*>(positions), sizeof(positions));
    bin.append(reinterpret_cast<const char*>(indices), sizeof(indices));
    write("quad.bin", bin);
    std::string list, node_json, mesh_json;
    for (size_t i = 0; i < nodes.size(); ++i) {
      list += (i ? ", " : "") + std::to_string(i);
      node_json += (i ? ", " : "") + nodes[i];
    }
    for (int m = 0; m < meshes; ++m)
      mesh_json += std::string(m ? ", " : "") +
                   R"({"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]})";
    return write(name + ".gltf",
                 R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [)" + list +
                     R"(]}], "nodes": [)" + node_json + R"(], "meshes": [)" + mesh_json +
                     R"(],
"buffers": [{"uri": "quad.bin", "byteLength": 60}],
"bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                {"buffer": 0, "byteOffset": 48, "byteLength": 12}],
"accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
               "min": [0, 0, 0], "max": [1, 1, 0]},
              {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}]})")
        .string();
  }
  // One clear line, exit code 2, and the line mentions `needle`.
  void expect_bad_input(const Result& r, const std::string& needle) {
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(r.err_lines(), 1) << r.err;
    EXPECT_NE(r.err.find(needle), std::string::npos) << "stderr: " << r.err;
  }
  fs::path dir_;
};

}  // namespace illum_cli_test

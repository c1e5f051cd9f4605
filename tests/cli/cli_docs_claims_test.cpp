// Claims of README.md and docs/*.md that only the real program and scripts can show
// (tests/README.md, "Claims and the tests that back them"): every `illum` command the pages
// show runs as written (smaller sizes), the quick-start script renders the Cornell box into
// the current folder, install-deps.sh skips when all is present and uses sudo only when not
// root, images are limited to 16384 pixels a side, the progress bar appears on a terminal only,
// `info` lists what the README says, and a scene file's settings are defaults that options
// override.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "../scene/gltf_asset.h"
#include "cli_fixture.h"
#include "illum/core/image.h"
#include "test_support/prerequisites.h"

using namespace illum_cli_test;

namespace {

const fs::path kSource = ILLUM_SOURCE_DIR;

std::string quoted(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::vector<std::string> split_words(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> words;
  for (std::string w; in >> w;) words.push_back(w);
  return words;
}

// The `illum ...` commands inside the fenced code blocks of a Markdown page, with `\`
// continuations joined and `# comments` dropped.
std::vector<std::vector<std::string>> fenced_commands(const std::string& page) {
  std::vector<std::vector<std::string>> commands;
  std::istringstream in(page);
  bool fenced = false;
  std::string pending;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("```", 0) == 0) {
      fenced = !fenced;
      continue;
    }
    if (!fenced) continue;
    const size_t hash = line.find(" #");
    if (hash != std::string::npos) line.resize(hash);
    while (!line.empty() && line.back() == ' ') line.pop_back();
    const bool continued = !line.empty() && line.back() == '\\';
    if (continued) line.pop_back();
    pending += " " + line;
    if (continued) continue;
    const std::vector<std::string> words = split_words(pending);
    pending.clear();
    if (words.size() > 1 && words[0] == "illum")
      commands.emplace_back(words.begin() + 1, words.end());
  }
  return commands;
}

// `illum ...` commands written as inline code (`...`) anywhere in a page.
std::vector<std::vector<std::string>> inline_commands(const std::string& page) {
  std::vector<std::vector<std::string>> commands;
  for (size_t at = page.find("`illum "); at != std::string::npos; at = page.find("`illum ", at)) {
    const size_t end = page.find('`', at + 1);
    const std::vector<std::string> words = split_words(page.substr(at + 1, end - at - 1));
    commands.emplace_back(words.begin() + 1, words.end());
    at = end + 1;
  }
  return commands;
}

class DocsClaims : public CliTest {
 protected:
  // Runs `command` (a shell command line) in `cwd` under a time limit, with no display, so
  // `illum view` takes its documented headless fallback.
  Result run_shell_in(const fs::path& cwd, const std::string& command, int seconds = 120) {
    const fs::path out = dir_ / "stdout.txt", err = dir_ / "stderr.txt";
    const std::string cmd = "cd " + quoted(cwd.string()) +
                            " && env -u DISPLAY -u WAYLAND_DISPLAY timeout " +
                            std::to_string(seconds) + " " + command + " >" + out.string() + " 2>" +
                            err.string() + " </dev/null";
    const int status = std::system(cmd.c_str());
    Result r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.out = slurp(out);
    r.err = slurp(err);
    return r;
  }

  // Runs each documented command in one working folder, in page order (a bake feeds the
  // `--baked` of a later frame), shrunk so the page costs a few seconds: sizes, samples,
  // frames and photon counts are capped, and `sibenik` becomes `cornell` (loading Sibenik is
  // SharedScenes.SibenikBuiltin's; what is checked here is that each option exists, is
  // accepted together with the others and writes what the page says). A command fails the
  // test if it exits non-zero or leaves out a file it names.
  void run_documented(const std::vector<std::vector<std::string>>& commands,
                      const std::string& page) {
    ASSERT_FALSE(commands.empty()) << page << ": no `illum` commands found";
    const fs::path work = dir_ / "work";
    fs::create_directories(work);
    write("work/scene.gltf", illum::test::gltf_text(illum::test::make_asset()));
    const std::map<std::string, long long> caps = {{"--width", 16}, {"--height", 16},
                                                   {"--spp", 2},    {"--resolution", 32},
                                                   {"--frames", 2}, {"--warmup", 1}};
    const std::map<std::string, std::string> param_caps = {{"photons", "2000"},
                                                           {"photons_per_iteration", "2000"},
                                                           {"iterations", "2"},
                                                           {"gather_rays", "2"},
                                                           {"shadow_resolution", "64"}};
    int ran = 0;
    for (std::vector<std::string> args : commands) {
      const std::string shown = "illum " + [&] {
        std::string s;
        for (const auto& a : args) s += (s.empty() ? "" : " ") + a;
        return s;
      }();
      SCOPED_TRACE(page + ": " + shown);
#ifndef ILLUM_HAVE_GPU
      if (args[0] == "frame" || args[0] == "view") continue;  // not built without the GPU layer
#endif
      if (args.size() > 1 && args[1] == "sibenik") args[1] = "cornell";
      std::set<std::string> given;
      std::vector<fs::path> outputs;
      for (size_t i = 0; i < args.size(); ++i) {
        given.insert(args[i]);
        if (i + 1 >= args.size()) break;
        const std::string& next = args[i + 1];
        if (caps.count(args[i])) {
          args[i + 1] = std::to_string(std::min(std::stoll(next), caps.at(args[i])));
        } else if (args[i] == "-p" || args[i] == "--param") {
          const std::string key = next.substr(0, next.find('='));
          if (param_caps.count(key)) args[i + 1] = key + "=" + param_caps.at(key);
        } else if (args[i] == "-o" || args[i] == "--output") {
          const fs::path o = work / next;
          outputs.push_back(args[0] == "bake" ? o / "lightmap.json" : o);
          const std::string ext = o.extension().string();
          if (args[0] == "render" && (ext == ".exr" || ext == ".hdr"))
            outputs.push_back(fs::path(o).replace_extension(".png"));
        } else if (args[i] == "--json" || args[i] == "--camera-out") {
          outputs.push_back(work / next);
        }
      }
      const bool sized = args[0] == "render" || args[0] == "frame" || args[0] == "view";
      if (sized && !given.count("--width")) args.insert(args.end(), {"--width", "16"});
      if (sized && !given.count("--height")) args.insert(args.end(), {"--height", "16"});
      // Radiosity and --basis none (the extra maps alone) take no --spp.
      const bool no_spp = std::find(args.begin(), args.end(), "radiosity") != args.end() ||
                          std::find(args.begin(), args.end(), "none") != args.end();
      if ((args[0] == "render" || (args[0] == "bake" && !no_spp)) && !given.count("--spp"))
        args.insert(args.end(), {"--spp", "2"});
      if (args[0] == "bake" && !given.count("--resolution"))
        args.insert(args.end(), {"--resolution", "32"});
      if (args[0] == "view") outputs.push_back(work / "view.png");  // the headless fallback
      for (const fs::path& o : outputs)
        fs::remove_all(o.filename() == "lightmap.json" ? o.parent_path() : o);

      std::string command = quoted(std::string(ILLUM_BINARY_DIR) + "/bin/illum");
      for (const std::string& a : args) command += " " + quoted(a);
      const auto start = std::chrono::steady_clock::now();
      const Result r = run_shell_in(work, command);
      std::printf("%.2f s: %s\n",
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                  command.c_str());
      EXPECT_EQ(r.exit_code, 0) << r.err;
      for (const fs::path& o : outputs) EXPECT_TRUE(fs::exists(o)) << o << " not written";
      ++ran;
    }
    EXPECT_GT(ran, 0);
  }
};

TEST_F(DocsClaims, ReadmeCommandsRunAsShown) {
  run_documented(fenced_commands(slurp(kSource / "README.md")), "README.md");
}

TEST_F(DocsClaims, LightmapPageCommandsRunAsShown) {
  run_documented(fenced_commands(slurp(kSource / "docs/lightmaps.md")), "docs/lightmaps.md");
}

TEST_F(DocsClaims, LightmapRadiosityPageCommandsRunAsShown) {
  run_documented(fenced_commands(slurp(kSource / "docs/lightmap-radiosity.md")),
                 "docs/lightmap-radiosity.md");
}

TEST_F(DocsClaims, LightmapExportPageCommandsRunAsShown) {
  run_documented(fenced_commands(slurp(kSource / "docs/lightmap-export.md")),
                 "docs/lightmap-export.md");
}

TEST_F(DocsClaims, ImageCommandsRunAsShown) {
  run_documented(inline_commands(slurp(kSource / "docs/images/README.md")),
                 "docs/images/README.md");
}

#ifdef ILLUM_HAVE_GPU
TEST_F(DocsClaims, RealtimePageCommandsRunAsShown) {
  run_documented(fenced_commands(slurp(kSource / "docs/realtime.md")), "docs/realtime.md");
}
#endif

// README, Quick start: "scripts/quickstart.sh installs the Debian packages, builds,
// path-traces the built-in Cornell box to ./cornell.png"; "`illum` is in build/release/bin/
// after the quick start"; both scripts call install-deps.sh. The script's own render line is
// run here (at 16×16) in a fresh folder; the install and the build are what CI does anyway.
TEST_F(DocsClaims, QuickstartRendersTheCornellBoxIntoTheCurrentFolder) {
  const std::string script = slurp(kSource / "scripts/quickstart.sh");
  EXPECT_NE(script.find("\n\"$root/scripts/install-deps.sh\"\n"), std::string::npos);
  EXPECT_NE(script.find("\ncmake --preset release "), std::string::npos);
  EXPECT_NE(script.find("\ncmake --build \"$root/build/release\""), std::string::npos);
  EXPECT_NE(slurp(kSource / "scripts/test.sh").find("\n\"$root/scripts/install-deps.sh\"\n"),
            std::string::npos);
  const std::string binary = "\"$root/build/release/bin/illum\" ";
  const size_t at = script.find("\n" + binary);
  ASSERT_NE(at, std::string::npos) << "quickstart.sh no longer runs build/release/bin/illum";
  const std::string line =
      script.substr(at + 1 + binary.size(), script.find('\n', at + 1) - at - 1 - binary.size());
  const std::vector<std::string> args = split_words(line);
  ASSERT_GE(args.size(), 2u);
  EXPECT_EQ(args[0], "render");
  EXPECT_EQ(args[1], "cornell");
  const auto value_of = [&](const std::string& a, const std::string& b) {
    for (size_t i = 0; i + 1 < args.size(); ++i)
      if (args[i] == a || args[i] == b) return args[i + 1];
    return std::string("(default)");
  };
  const std::string integrator = value_of("--integrator", "-i");
  EXPECT_TRUE(integrator == "path" || integrator == "(default)") << "path-traces: " << line;
  EXPECT_EQ(value_of("-o", "--output"), "cornell.png") << line;

  const fs::path cwd = dir_ / "somewhere";
  fs::create_directories(cwd);
  const Result r = run_shell_in(cwd, quoted(std::string(ILLUM_BINARY_DIR) + "/bin/illum") + " " +
                                         line + " --width 16 --height 16");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const illum::Image image = illum::read_image((cwd / "cornell.png").string());
  EXPECT_EQ(image.width(), 16);
  float sum = 0.0f;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) sum += image.pixel(x, y)[0];
  EXPECT_GT(sum, 0.0f) << "the Cornell box is lit, not a black image";
}

// README: install-deps.sh "installs every package the build needs with apt-get (it uses sudo
// when not run as root, and does nothing when all are present)". Run against stand-ins for
// dpkg-query, id, sudo and apt-get that record what they were asked.
TEST_F(DocsClaims, InstallDepsDoesNothingWhenAllArePresentAndUsesSudoOnlyWhenNotRoot) {
  const fs::path bin = dir_ / "bin";
  fs::create_directories(bin);
  const auto stub = [&](const std::string& name, const std::string& body) {
    write("bin/" + name, "#!/bin/sh\n" + body + "\n");
    fs::permissions(bin / name, fs::perms::owner_all);
  };
  const fs::path log = dir_ / "calls.txt";
  stub("dpkg-query",
       "for a; do p=$a; done\ncase \" $MISSING \" in *\" $p \"*) exit 1;; esac\n"
       "printf 'install ok installed'");
  stub("id", "echo \"$FAKE_UID\"");
  stub("sudo", "echo \"sudo $*\" >>" + log.string() + "\nexec \"$@\"");
  stub("apt-get", "echo \"apt-get $*\" >>" + log.string());
  const auto install = [&](const std::string& missing, const std::string& uid) {
    fs::remove(log);
    return run_shell_in(dir_, "env PATH=" + quoted(bin.string()) + ":\"$PATH\" MISSING=" +
                                  quoted(missing) + " FAKE_UID=" + uid + " bash " +
                                  quoted((kSource / "scripts/install-deps.sh").string()));
  };
  Result r = install("", "1000");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("packages present"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(log)) << "nothing to install, yet it ran: " << slurp(log);

  r = install("xdotool", "0");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::string calls = slurp(log);
  EXPECT_EQ(calls.find("sudo"), std::string::npos) << "root needs no sudo: " << calls;
  EXPECT_NE(calls.find("apt-get update"), std::string::npos) << calls;
  EXPECT_NE(calls.find("apt-get install"), std::string::npos) << calls;
  EXPECT_NE(calls.find("xdotool"), std::string::npos) << calls;

  r = install("xdotool", "1000");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  calls = slurp(log);
  EXPECT_NE(calls.find("sudo apt-get install"), std::string::npos) << calls;
  EXPECT_NE(calls.find("sudo apt-get update"), std::string::npos) << calls;
}

// README: "Images are limited to 16384 pixels a side (--width/--height above that are
// refused)" — the light-map atlas too; 16384 itself is accepted.
TEST_F(DocsClaims, ImagesAreLimitedTo16384PixelsASide) {
  const fs::path png = dir_ / "x.png";
  expect_bad_input(run("render cornell -i ao --spp 1 --width 16385 --height 1 -o " + png.string()),
                   "width");
  expect_bad_input(run("render cornell -i ao --spp 1 --width 1 --height 16385 -o " + png.string()),
                   "height");
  const Result big_atlas =
      run("bake cornell --spp 1 --resolution 16385 -o " + (dir_ / "lm").string());
  expect_bad_input(big_atlas, "16384");
  expect_bad_input(big_atlas, "--resolution");
#ifdef ILLUM_HAVE_GPU
  expect_bad_input(run("frame cornell --width 16385 --height 16 -o " + png.string()), "width");
  expect_bad_input(run("view cornell --height 16385 --close-after-frames 1"), "height");
#endif
  EXPECT_FALSE(fs::exists(png));
  EXPECT_FALSE(fs::exists(dir_ / "lm"));
  const Result r = run("render cornell -i ao --spp 1 --width 16384 --height 1 -o " + png.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(illum::read_image(png.string()).width(), 16384);
}

// DESIGN.md, Conventions: "Long work shows a progress bar with ETA on a terminal; when
// stderr is a file or a pipe ... a plain line every 5 s instead ... nothing for work done
// sooner". On a pseudo-terminal (`script`) the bar is drawn; piped, a short render's stderr
// holds only the one summary line (the lines themselves: CliAppBinary.ProgressLines...).
TEST_F(DocsClaims, ProgressBarOnATerminalOnly) {
  ILLUM_REQUIRE_PROGRAM("script");
  const std::string render = quoted(std::string(ILLUM_BINARY_DIR) + "/bin/illum") +
                             " render cornell -i path --width 16 --height 16 --spp 4 -o ";
  const Result piped = run_shell_in(dir_, render + "piped.png");
  ASSERT_EQ(piped.exit_code, 0) << piped.err;
  EXPECT_EQ(piped.err_lines(), 1) << piped.err;
  EXPECT_EQ(piped.err.find('\r'), std::string::npos) << piped.err;
  EXPECT_EQ(piped.err.find("ETA"), std::string::npos) << piped.err;
  const Result tty = run_shell_in(dir_, "script -qec " + quoted(render + "tty.png") + " /dev/null");
  ASSERT_EQ(tty.exit_code, 0) << tty.out << tty.err;
  EXPECT_NE(tty.out.find("ETA"), std::string::npos) << tty.out;
  EXPECT_NE(tty.out.find('\r'), std::string::npos) << tty.out;
}

// README: `illum info` prints "triangles, lights, materials, bounds, warnings".
TEST_F(DocsClaims, InfoListsWhatTheReadmeSays) {
  const Result r = run("info cornell");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* field : {"triangles", "lights", "materials", "bounds", "warnings"})
    EXPECT_NE(r.out.find(std::string("\n") + field + " "), std::string::npos) << field << "\n"
                                                                              << r.out;
}

// docs/scene-format.md: "Settings are defaults for jobs; command-line options override them."
TEST_F(DocsClaims, SceneSettingsAreDefaultsThatOptionsOverride) {
  write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const fs::path scene = write("s.illum.json", R"({"meshes": [{"file": "tri.obj"}],
    "environment": {"constant": [1, 1, 1]},
    "settings": {"width": 24, "height": 8, "spp": 1}})");
  const fs::path png = dir_ / "s.png";
  ASSERT_EQ(run("render " + scene.string() + " -i ao -o " + png.string()).exit_code, 0);
  illum::Image image = illum::read_image(png.string());
  EXPECT_EQ(image.width(), 24);
  EXPECT_EQ(image.height(), 8);
  ASSERT_EQ(run("render " + scene.string() + " -i ao --width 10 -o " + png.string()).exit_code, 0);
  image = illum::read_image(png.string());
  EXPECT_EQ(image.width(), 10);
  EXPECT_EQ(image.height(), 8);
}

// docs/lightmaps.md, Pipeline: `illum bake` denoises by default (strength 3; `-p
// denoise=false` for the raw estimate) and dilates the borders in 4 passes; the manifest
// records what was done.
TEST_F(DocsClaims, BakeDefaultsAsDocumented) {
  const fs::path lm = dir_ / "lm", raw = dir_ / "raw";
  ASSERT_EQ(run("bake cornell --resolution 32 --spp 1 -o " + lm.string()).exit_code, 0);
  const std::string manifest = slurp(lm / "lightmap.json");
  EXPECT_NE(manifest.find("\"denoise\": true"), std::string::npos) << manifest;
  EXPECT_NE(manifest.find("\"denoise_strength\": 3.0,"), std::string::npos) << manifest;
  EXPECT_NE(manifest.find("\"dilate\": 4,"), std::string::npos) << manifest;
  ASSERT_EQ(
      run("bake cornell --resolution 32 --spp 1 -p denoise=false -o " + raw.string()).exit_code, 0);
  EXPECT_NE(slurp(raw / "lightmap.json").find("\"denoise\": false"), std::string::npos);
}

#ifdef ILLUM_HAVE_GPU
// docs/realtime.md, Errors: "no Vulkan device → `no Vulkan device found: install
// mesa-vulkan-drivers (lavapipe) or a GPU driver`". The loader is pointed at a driver list
// that does not exist, as on a machine without any Vulkan driver: one line, exit 2, no image.
TEST_F(DocsClaims, NoVulkanDeviceIsOneLineNamingTheFix) {
  const std::string no_driver =
      "env VK_ICD_FILENAMES=/nonexistent/icd.json VK_DRIVER_FILES=/nonexistent/icd.json " +
      quoted(std::string(ILLUM_BINARY_DIR) + "/bin/illum");
  const std::string message = "no Vulkan device found: install mesa-vulkan-drivers (lavapipe)";
  const fs::path png = dir_ / "frame.png";
  expect_bad_input(
      run_shell_in(dir_, no_driver + " frame cornell --width 16 --height 16 -o " + png.string()),
      message);
  EXPECT_FALSE(fs::exists(png));
  // `illum view` without a display first says it falls back to one headless frame
  // (realtime.md, illum view), then fails the same way, writing nothing.
  const Result view = run_shell_in(dir_, no_driver + " view cornell");
  EXPECT_EQ(view.exit_code, 2) << view.err;
  EXPECT_NE(view.err.find("illum: error: " + message), std::string::npos) << view.err;
  EXPECT_FALSE(fs::exists(dir_ / "view.png"));
}
#endif

}  // namespace

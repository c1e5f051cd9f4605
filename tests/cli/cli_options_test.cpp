// Every option of every `illum` subcommand refuses bad values: one stderr line naming the
// option, exit code 2, no output written. The options are not listed here: they are read
// from `illum --help` and `illum SUB --help`, so an option added later without validation
// fails these tests. Numeric options (INT, UINT, FLOAT in the help) get malformed numbers
// (empty, NaN, ±inf, 1e99, text, trailing text, a 64-bit overflow, a negative number);
// every option taking a value gets an empty one; `-p` gets repeated and empty keys. Also
// zero-sized frames and windows, and scene files whose values only the real-time renderer
// refuses.
#include <map>
#include <regex>
#include <set>
#include <vector>

#include "cli_fixture.h"

using namespace illum_cli_test;

namespace {

struct HelpOption {
  std::string name;  // "--width", or a positional's name ("scene")
  std::string type;  // TEXT, INT, UINT, FLOAT
};

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  size_t start = 0;
  while (start < text.size()) {
    const size_t end = text.find('\n', start);
    lines.push_back(text.substr(start, end == std::string::npos ? std::string::npos : end - start));
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return lines;
}

// The options CLI11 lists in a help text: "  -o,--output TEXT REQUIRED ...", "  --width
// INT:in [1, 16384] ...", positionals "  scene TEXT REQUIRED ..."; flags have no type.
std::vector<HelpOption> parse_help(const std::string& help) {
  static const std::regex option(
      R"(^\s+(?:-[A-Za-z],)?(--[A-Za-z0-9-]+)\s+(TEXT|INT|UINT|FLOAT)\b)");
  static const std::regex positional(R"(^\s+([a-z][a-z0-9_]*)\s+(TEXT|INT|UINT|FLOAT)\b)");
  std::vector<HelpOption> out;
  bool in_positionals = false;
  for (const std::string& line : split_lines(help)) {
    if (line.rfind("Positionals:", 0) == 0) in_positionals = true;
    if (line.rfind("Options:", 0) == 0 || line.rfind("Subcommands:", 0) == 0)
      in_positionals = false;
    std::smatch m;
    if (std::regex_search(line, m, option) ||
        (in_positionals && std::regex_search(line, m, positional)))
      out.push_back({m[1], m[2]});
  }
  return out;
}

std::vector<std::string> parse_subcommands(const std::string& help) {
  static const std::regex entry(R"(^  ([a-z]+)\s)");
  std::vector<std::string> out;
  bool in_list = false;
  for (const std::string& line : split_lines(help)) {
    if (line.rfind("Subcommands:", 0) == 0) {
      in_list = true;
      continue;
    }
    std::smatch m;
    if (in_list && std::regex_search(line, m, entry)) out.push_back(m[1]);
  }
  return out;
}

bool is_numeric(const std::string& type) {
  return type == "INT" || type == "UINT" || type == "FLOAT";
}

// Numeric options that may legitimately take a negative value; every other numeric option
// must refuse "-1". `relight --rotate` turns the environment either way.
const std::set<std::string> kNegativeAllowed = {"relight --rotate"};

class CliOptionsTest : public CliTest {
 protected:
  void SetUp() override {
    CliTest::SetUp();
    // `illum view` must not open a window here: it renders headless, or a wrongly accepted
    // `--close-after-frames ''` (0: until closed) would wait for a person.
    ::unsetenv("DISPLAY");
    ::unsetenv("WAYLAND_DISPLAY");
  }
  // A cheap valid invocation of each subcommand (so that an option that is wrongly
  // accepted runs briefly instead of for minutes), as (option, value) pairs after the
  // positionals; the option under test is left out of it (CLI11 refuses an option given
  // twice, which would hide a missing check).
  std::string invocation(const std::string& sub, const std::string& tested) {
    const std::string out = (dir_ / "out.png").string();
    const std::map<std::string, std::vector<std::pair<std::string, std::string>>> base = {
        {"info", {}},
        {"render",
         {{"-i", "ao"}, {"--width", "8"}, {"--height", "8"}, {"--spp", "1"}, {"-o", out}}},
        {"bake", {{"--resolution", "32"}, {"--spp", "1"}, {"-o", (dir_ / "lightmap").string()}}},
        {"frame", {{"--width", "8"}, {"--height", "8"}, {"-o", out}}},
        {"view",
         {{"--width", "8"},
          {"--height", "8"},
          {"--close-after-frames", "1"},
          {"--fallback-output", out}}},
        {"relight",
         {{"--baked", (dir_ / "prt").string()},
          {"--sun", "0,-1,0"},
          {"--width", "8"},
          {"--height", "8"},
          {"--spp", "1"},
          {"-o", out}}},
        {"export",
         {{"--baked", (dir_ / "lightmap").string()}, {"-o", (dir_ / "out.glb").string()}}},
    };
    const auto it = base.find(sub);
    if (it == base.end()) {
      ADD_FAILURE() << "no cheap invocation of 'illum " << sub << "' in this test: add one";
      return sub + " cornell";
    }
    std::string args = sub + (tested == "scene" ? "" : " cornell");
    for (const auto& [option, value] : it->second) {
      const bool same = option == tested || (option == "-o" && tested == "--output") ||
                        (option == "-i" && tested == "--integrator");
      if (!same) args += " " + option + " '" + value + "'";
    }
    return args;
  }

  // The files in the folder, but for the fixture's stdout/stderr captures.
  std::set<std::string> files() {
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_)) {
      const std::string name = e.path().filename().string();
      if (name != "stdout.txt" && name != "stderr.txt") names.insert(name);
    }
    return names;
  }

  // Bad input: one line naming `needle`, exit 2, and no file added to the folder.
  void expect_refused(const std::string& args, const std::string& needle) {
    SCOPED_TRACE("illum " + args);
    const std::set<std::string> before = files();
    expect_bad_input(run(args), needle);
    for (const std::string& name : files())
      if (!before.count(name)) {
        ADD_FAILURE() << "wrote " << name;
        fs::remove_all(dir_ / name);
      }
  }

  std::vector<std::string> subcommands() {
    const Result r = run("--help");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return parse_subcommands(r.out);
  }

  std::vector<HelpOption> options_of(const std::string& sub) {
    const Result r = run(sub + " --help");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return parse_help(r.out);
  }
};

// The help parsing finds what is known to be there (so the tests below cannot pass by
// finding nothing).
TEST_F(CliOptionsTest, HelpListsTheKnownOptions) {
  const std::vector<std::string> subs = subcommands();
  for (const char* known : {"info", "render", "bake"})
    EXPECT_NE(std::find(subs.begin(), subs.end(), known), subs.end()) << known;
#ifdef ILLUM_HAVE_GPU
  for (const char* known : {"frame", "view"})
    EXPECT_NE(std::find(subs.begin(), subs.end(), known), subs.end()) << known;
#endif
  std::map<std::string, std::string> render;
  for (const HelpOption& o : options_of("render")) render[o.name] = o.type;
  EXPECT_EQ(render["--seed"], "UINT");
  EXPECT_EQ(render["--width"], "INT");
  EXPECT_EQ(render["--time"], "FLOAT");
  EXPECT_EQ(render["--exposure"], "FLOAT");
  EXPECT_EQ(render["--output"], "TEXT");
  EXPECT_EQ(render["scene"], "TEXT");
  EXPECT_EQ(render.count("--no-preview"), 0u) << "a flag takes no value";
}

// Help states ranges a user can read: no float limits such as 1.1754944e-38 or 3.4e+38.
TEST_F(CliOptionsTest, HelpShowsNoInternalBounds) {
  for (const std::string& sub : subcommands()) {
    const Result r = run(sub + " --help");
    EXPECT_EQ(r.exit_code, 0) << sub;
    for (const char* internal : {"e-38", "e+38", "e-45", "e+308"})
      EXPECT_EQ(r.out.find(internal), std::string::npos) << "illum " << sub << " --help:\n"
                                                         << r.out;
  }
}

TEST_F(CliOptionsTest, EveryNumericOptionRefusesMalformedNumbers) {
  // 1e99 overflows a float and lies past every double option's range.
  const std::vector<std::string> bad = {"''", "nan", "inf", "-inf", "1e99", "abc", "12x", "0x10"};
  size_t numeric = 0;
  for (const std::string& sub : subcommands())
    for (const HelpOption& o : options_of(sub)) {
      if (!is_numeric(o.type)) continue;
      ++numeric;
      std::vector<std::string> values = bad;
      if (o.type != "FLOAT") values.push_back("99999999999999999999999");  // past 64 bits
      if (!kNegativeAllowed.count(sub + " " + o.name)) values.push_back("-1");
      for (const std::string& value : values)
        expect_refused(invocation(sub, o.name) + " " + o.name + " " + value, o.name);
    }
    // render 7, bake 6, frame 5, view 4 (the real-time ones only with the GPU layer).
#ifdef ILLUM_HAVE_GPU
  EXPECT_GE(numeric, 22u);
#else
  EXPECT_GE(numeric, 13u);
#endif
}

// A leading zero is decimal, not octal (CLI11 alone reads "010" as 8).
TEST_F(CliOptionsTest, LeadingZerosAreDecimal) {
  const fs::path out = dir_ / "ao.exr";
  const Result r =
      run("render cornell -i ao --width 010 --height 4 --spp 1 --no-preview -o " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("ao 10x4"), std::string::npos) << r.err;
}

TEST_F(CliOptionsTest, EveryOptionRefusesAnEmptyValue) {
  size_t checked = 0;
  for (const std::string& sub : subcommands())
    for (const HelpOption& o : options_of(sub)) {
      ++checked;
      if (o.name == "scene")
        expect_refused(invocation(sub, "scene") + " ''", "scene");
      else
        expect_refused(invocation(sub, o.name) + " " + o.name + " ''", o.name);
    }
  expect_refused("--log '' info cornell", "--log");
  EXPECT_GE(checked, 20u);
}

// Keys each subcommand knows, so that the repetition or the missing value is the only fault
// (an unknown key would be refused for being unknown).
TEST_F(CliOptionsTest, ParamKeysRepeatedOrEmpty) {
  const std::map<std::string, std::string> known = {
      {"render", "samples"}, {"bake", "padding"}, {"frame", "pcf_taps"}, {"view", "pcf_taps"}};
  size_t checked = 0;
  for (const std::string& sub : subcommands())
    for (const HelpOption& o : options_of(sub)) {
      if (o.name != "--param") continue;
      ++checked;
      const auto key = known.find(sub);
      if (key == known.end()) {
        ADD_FAILURE() << "add a --param key that 'illum " << sub << "' knows to this test";
        continue;
      }
      const std::string k = key->second;
      expect_refused(invocation(sub, "") + " -p " + k + "=1 -p " + k + "=2",
                     "'" + k + "' is given more than once");
      expect_refused(invocation(sub, "") + " -p " + k + "=", "'" + k + "=' has no value");
      expect_refused(invocation(sub, "") + " --param =3", "'=3'");
    }
  EXPECT_GE(checked, 2u);  // render and bake (and frame)
}

// A -p key that a dedicated option sets is refused, naming the option (it was silently
// overwritten by the option's default).
TEST_F(CliOptionsTest, ParamKeysOfDedicatedOptions) {
  expect_refused(invocation("bake", "") + " -p spp=4", "--spp");
  expect_refused(invocation("bake", "") + " -p seed=4", "--seed");
#ifdef ILLUM_HAVE_GPU
  expect_refused(invocation("frame", "") + " -p exposure=2", "--exposure");
  expect_refused(invocation("frame", "") + " -p width=16", "--width");
#endif
}

#ifdef ILLUM_HAVE_GPU

TEST_F(CliOptionsTest, ZeroSizedFramesAndWindows) {
  for (const char* option : {"--width", "--height"}) {
    expect_refused(invocation("frame", option) + " " + option + " 0", option);
    expect_refused(invocation("view", option) + " " + option + " 0", option);
  }
}

// Scene files whose values the scene loader takes but the real-time renderer refuses: a
// light position that overflows a float to infinity, an emitter scaled to zero area (1e-25
// on two axes: the loader's zero-scale check passes, the area underflows). And one the
// loader refuses first (a negative flux). One line naming the file, exit 2, no image.
TEST_F(CliOptionsTest, RealtimeRendererRefusesBadSceneValues) {
  write("room.mtl", "newmtl white\nKd 0.7 0.7 0.7\nnewmtl glow\nKd 0 0 0\nKe 5 5 5\n");
  write("floor.obj",
        "mtllib room.mtl\nv 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nusemtl white\nf 1 3 2\nf 1 4 3\n");
  write("lamp.obj",
        "mtllib room.mtl\no lamp\nv 0 1 0\nv 0.2 1 0\nv 0.2 1 0.2\nv 0 1 0.2\n"
        "usemtl glow\nf 1 2 3\nf 1 3 4\n");
  const std::string camera = R"("camera": {"position": [0.5, 2, 2], "look_at": [0.5, 0, 0.5]})";
  const std::string inf_position =
      write("inf_position.illum.json",
            R"({"meshes": [{"file": "floor.obj"}], )" + camera +
                R"(, "lights": [{"type": "point", "position": [1e39, 1, 0], "intensity": 1}]})")
          .string();
  const std::string zero_area =
      write("zero_area.illum.json",
            R"({"meshes": [{"file": "floor.obj"}, {"file": "lamp.obj", "transform": )"
            R"({"scale": [1e-25, 1, 1e-25]}}], )" +
                camera + "}")
          .string();
  const std::string negative_flux =
      write("negative_flux.illum.json",
            R"({"meshes": [{"file": "floor.obj"}], )" + camera +
                R"(, "lights": [{"type": "point", "position": [0, 1, 0], "flux": -5}]})")
          .string();
  const std::string frame = " --width 8 --height 8 -o " + (dir_ / "f.png").string();
  const std::string view =
      " --width 8 --height 8 --close-after-frames 1 --fallback-output " + (dir_ / "v.png").string();
  // The loader refuses the overflowed position and the negative flux before the renderer
  // sees them (scene_validation); the zero-area emitter only the renderer can refuse.
  for (const std::string& options : {frame, view}) {
    const std::string sub = options == frame ? "frame " : "view ";
    expect_refused(sub + inf_position + options, "inf_position.illum.json: light 0");
    expect_refused(sub + inf_position + options, "is not finite");
    expect_refused(sub + zero_area + options, "zero_area.illum.json: area light 'lamp'");
    expect_refused(sub + zero_area + options, "zero area");
    expect_refused(sub + negative_flux + options, "flux");
  }
}

#endif

}  // namespace

// One CLI: every option of every subcommand, read from the CLI11 app itself (build_app(),
// apps/illum/app.cpp), uses the one name of its concept, lists its choices in help, and
// shows no internal float bound; and, through the `illum` binary, the messages for a
// mistyped option or -p key, app options after the subcommand, and progress lines when
// stderr is a file.
#include <map>
#include <regex>
#include <set>

#include "cli_fixture.h"
#include "commands.h"
#include "illum/render/integrator.h"

using namespace illum_cli_test;

namespace {

std::unique_ptr<CLI::App> app() {
  static std::string log_level;
  return illum::cli::build_app(&log_level);
}

// Every "--name" and "-x" of an option.
std::vector<std::string> names_of(const CLI::Option* option) {
  std::vector<std::string> names;
  for (const std::string& l : option->get_lnames()) names.push_back("--" + l);
  for (const std::string& s : option->get_snames()) names.push_back("-" + s);
  return names;
}

// subcommand → its option names ("" is the app).
std::map<std::string, std::set<std::string>> all_options(CLI::App& a) {
  std::map<std::string, std::set<std::string>> out;
  for (const CLI::Option* o : a.get_options())
    for (const std::string& n : names_of(o)) out[""].insert(n);
  for (CLI::App* sub : a.get_subcommands({}))
    for (const CLI::Option* o : sub->get_options())
      for (const std::string& n : names_of(o)) out[sub->get_name()].insert(n);
  return out;
}

// One name per concept: the canonical name, and the synonyms no subcommand may use.
struct Concept {
  const char* canonical;
  std::set<std::string> commands;  // the subcommands that must have it
  std::vector<const char*> banned;
};

const std::map<std::string, Concept>& concepts() {
  static const std::map<std::string, Concept> table = {
      {"bounces",
       {"--bounces",
        {"render", "bake"},
        {"--max-bounces", "--max-depth", "--depth", "--max_bounces", "--path-length"}}},
      {"baked input",
       {"--baked",
        {"frame", "view", "export", "relight"},
        {"--lightmap", "--prt", "--probes", "--lightmaps", "--bake", "--folder"}}},
      {"timed frames", {"--frames", {"frame"}, {"--timed-frames", "--runs"}}},
      {"sun",
       {"--sun",
        {"render", "bake", "frame", "view", "relight"},
        {"--irradiance", "--sun-dir", "--sun-direction", "--sun-azimuth", "--sun-elevation"}}},
      {"sky",
       {"--sky",
        {"render", "bake", "frame", "view", "relight"},
        {"--env", "--environment", "--envmap"}}},
      {"tone mapper",
       {"--tonemap",
        {"render", "relight", "frame", "view"},
        {"--tone-map", "--tonemapper", "--tone-mapper"}}},
      {"exposure", {"--exposure", {"render", "relight", "frame", "view"}, {"--ev"}}},
      {"shadow method", {"--shadows", {"frame", "view"}, {"--shadow", "--shadow-method"}}},
      {"seed", {"--seed", {"render", "bake"}, {"--rng-seed", "--random-seed"}}},
      {"samples", {"--spp", {"render", "bake", "relight"}, {"--samples", "--spp-per-pixel"}}},
      {"width", {"--width", {"render", "frame", "view", "relight"}, {"-w", "--res-x"}}},
      {"height", {"--height", {"render", "frame", "view", "relight"}, {"--res-y"}}},
      {"output", {"--output", {"render", "bake", "frame", "relight", "export"}, {"--out"}}},
      {"threads", {"--threads", {"render", "bake", "relight"}, {"--jobs", "-j"}}},
      {"time budget", {"--time", {"render", "bake"}, {"--seconds", "--time-budget"}}},
      {"log level", {"--log", {""}, {"--log-level", "--verbose", "--quiet"}}},
  };
  return table;
}

// A name of one meaning, kept off the subcommands where it would mean another (`view` closes
// after N frames with --close-after-frames; `render`'s shadow rays are --shadow-rays).
const std::map<std::string, std::set<std::string>> kOnlyIn = {
    {"--frames", {"frame"}},
    {"--shadows", {"frame", "view"}},
};

TEST(CliAppOptions, EachConceptHasOneName) {
  auto a = app();
  const auto options = all_options(*a);
  ASSERT_GE(options.size(), 6u) << "the app lost its subcommands";
  for (const auto& [name, c] : concepts()) {
    for (const std::string& command : c.commands) {
      if (!options.count(command)) continue;  // frame/view without the GPU layer
      EXPECT_TRUE(options.at(command).count(c.canonical))
          << name << ": illum " << command << " has no " << c.canonical;
    }
    for (const auto& [command, names] : options)
      for (const char* banned : c.banned)
        EXPECT_FALSE(names.count(banned))
            << name << ": illum " << command << " names it " << banned << ", not " << c.canonical;
  }
  for (const auto& [option, commands] : kOnlyIn)
    for (const auto& [command, names] : options)
      EXPECT_TRUE(!names.count(option) || commands.count(command))
          << option << " means something else in illum " << command;
}

// Every option with a fixed set of values declares it (CLI11 IsMember): help shows
// "TEXT:{a,b,c}". The integrators are the registry's.
TEST(CliAppOptions, OptionsWithChoicesListThem) {
  const std::map<std::string, std::vector<std::string>> with_choices = {
      {"", {"--log"}},
      {"render", {"--integrator", "--bounce-mode", "--shadow-rays"}},
      {"bake", {"--method", "--basis", "--content", "--kind", "--mode"}},
      {"relight", {"--lookup"}},
      {"export", {"--tone"}},
      {"frame", {"--technique", "--shadows", "--tonemap", "--enable", "--disable"}},
      {"view", {"--technique", "--shadows", "--tonemap", "--enable", "--disable"}},
  };
  auto a = app();
  size_t checked = 0;
  for (const auto& [command, options] : with_choices) {
    CLI::App* owner = a.get();
    if (!command.empty()) {
      try {
        owner = a->get_subcommand(command);
      } catch (const CLI::OptionNotFound&) {
        continue;  // frame/view without the GPU layer
      }
    }
    const std::string help = owner->help();
    for (const std::string& name : options) {
      const CLI::Option* o = owner->get_option(name);
      EXPECT_NE(o->get_type_name().find('{'), std::string::npos)
          << "illum " << command << " " << name << " lists no choices: " << o->get_type_name();
      EXPECT_NE(help.find(o->get_type_name()), std::string::npos) << help;
      ++checked;
    }
  }
  EXPECT_GE(checked, 11u);
  const std::string integrators = a->get_subcommand("render")->get_option("-i")->get_type_name();
  for (const std::string& name : illum::Integrator::names())
    EXPECT_NE(integrators.find(name), std::string::npos) << integrators;
}

// A value outside the choices is refused while parsing, before any command runs.
TEST(CliAppOptions, ValuesOutsideTheChoicesAreRefused) {
  const std::vector<std::vector<std::string>> bad = {
      {"illum", "render", "cornell", "-o", "x.png", "-i", "pathh"},
      {"illum", "bake", "cornell", "-o", "d", "--basis", "rmn"},
      {"illum", "bake", "cornell", "-o", "d", "--kind", "probe"},
      {"illum", "relight", "cornell", "--baked", "d", "--sun", "0,-1,0", "-o", "x.png", "--lookup",
       "texel"},
  };
  for (const auto& args : bad) {
    auto a = app();
    std::vector<const char*> argv;
    for (const std::string& s : args) argv.push_back(s.c_str());
    EXPECT_THROW(a->parse(int(argv.size()), argv.data()), CLI::ValidationError) << args[1];
  }
}

// Help states ranges a person can read: no float limits such as 1.1754944e-38 or 1e+30.
TEST(CliAppOptions, HelpShowsNoInternalBounds) {
  auto a = app();
  static const std::regex exponent(R"([0-9]e[+-]?[0-9])");
  size_t helps = 0;
  for (CLI::App* sub : a->get_subcommands({})) {
    const std::string help = sub->help();
    std::smatch m;
    EXPECT_FALSE(std::regex_search(help, m, exponent))
        << "illum " << sub->get_name() << " --help shows " << m.str(0) << ":\n"
        << help;
    ++helps;
  }
  EXPECT_GE(helps, 5u);
}

class CliAppBinary : public CliTest {};

TEST_F(CliAppBinary, MistypedOptionGetsTheNearestName) {
  const Result r = run("bake cornell --resoluton 32 -o " + (dir_ / "d").string());
  expect_bad_input(r, "unknown option --resoluton of illum bake; did you mean --resolution?");
  EXPECT_FALSE(fs::exists(dir_ / "d"));
  // Far from every name: no guess, a pointer to the help.
  expect_bad_input(run("render cornell --zzzzzz -o " + (dir_ / "x.png").string()),
                   "unknown option --zzzzzz of illum render (see 'illum render --help')");
  // App options are candidates too.
  expect_bad_input(run("info cornell --lgo info"), "did you mean --log?");
}

TEST_F(CliAppBinary, UnknownParamKeyListsTheKnownKeys) {
  const std::string out = " -o " + (dir_ / "x.png").string();
  Result r = run("render cornell -i path --width 8 --height 8 --spp 1 -p rr_dept=2" + out);
  expect_bad_input(r, "'rr_dept' is not a known key; did you mean 'rr_depth'?");
  EXPECT_NE(r.err.find("(known: rr_depth)"), std::string::npos) << r.err;
  r = run("render cornell -i ao --width 8 --height 8 --spp 1 -p bogus=1" + out);
  expect_bad_input(r, "'bogus' is not a known key (known: ");
  r = run("bake cornell --resolution 32 --spp 1 -p dilat=2 -o " + (dir_ / "d").string());
  expect_bad_input(r, "did you mean 'dilate'?");
#ifdef ILLUM_HAVE_GPU
  r = run("frame cornell --width 8 --height 8 -p pcf_tap=8" + out);
  expect_bad_input(r, "-p pcf_tap: unknown parameter; did you mean pcf_taps?");
#endif
  EXPECT_FALSE(fs::exists(dir_ / "x.png"));
}

// No -p key duplicates a dedicated option: each is refused naming the option, and an option
// given to an integrator that has no use for it is refused too.
TEST_F(CliAppBinary, ParamKeysOfOptions) {
  const std::string base =
      "render cornell --width 8 --height 8 --spp 1 -o " + (dir_ / "x.png").string();
  expect_bad_input(run(base + " -i path -p max_bounces=2"), "set it with --bounces");
  expect_bad_input(run(base + " -i whitted -p max_depth=2"), "set it with --bounces");
  expect_bad_input(run(base + " -i path -p bounces=direct"), "set it with --bounce-mode");
  expect_bad_input(run(base + " -i whitted -p shadows=false"), "set it with --shadow-rays");
  expect_bad_input(run(base + " -i ao --bounces 2"), "--bounces does not apply to -i ao");
  expect_bad_input(run(base + " -i path --shadow-rays off"), "--shadow-rays does not apply");
}

// --bounces is the path length wherever it is given: 0 bounces on the path tracer is direct
// light only (a different image from 8), and it reaches the probe baker's manifest.
TEST_F(CliAppBinary, BouncesTakeEffect) {
  const std::string base = "render cornell -i path --width 16 --height 16 --spp 4 --seed 1 -o ";
  ASSERT_EQ(run(base + (dir_ / "b0.png").string() + " --bounces 0").exit_code, 0);
  ASSERT_EQ(run(base + (dir_ / "b8.png").string() + " --bounces 8").exit_code, 0);
  ASSERT_EQ(run(base + (dir_ / "d.png").string()).exit_code, 0);
  EXPECT_NE(slurp(dir_ / "b0.png"), slurp(dir_ / "b8.png"));
  EXPECT_EQ(slurp(dir_ / "d.png"), slurp(dir_ / "b8.png")) << "the default is 8";
  const Result p = run("bake cornell --kind probes --spp 4 --bounces 3 --spacing 0.25 -o " +
                       (dir_ / "probes").string());
  ASSERT_EQ(p.exit_code, 0) << p.err;
  EXPECT_NE(slurp(dir_ / "probes" / "probes.json").find("\"max_bounces\": 3"), std::string::npos);
  expect_bad_input(run("bake cornell --kind probes -p max_bounces=3 -o " + (dir_ / "p2").string()),
                   "set it with --bounces");
}

// `--log` after the subcommand is the app's option, as before it.
TEST_F(CliAppBinary, LogAfterTheSubcommand) {
  const std::string render =
      "render cornell -i ao --width 8 --height 8 --spp 1 -o " + (dir_ / "x.png").string();
  const Result before = run("--log debug " + render);
  const Result after = run(render + " --log debug");
  ASSERT_EQ(before.exit_code, 0) << before.err;
  ASSERT_EQ(after.exit_code, 0) << after.err;
  EXPECT_NE(after.err.find("[debug]"), std::string::npos) << after.err;
  EXPECT_EQ(std::count(before.err.begin(), before.err.end(), '\n'),
            std::count(after.err.begin(), after.err.end(), '\n'));
  expect_bad_input(run(render + " --log loud"), "--log");
  EXPECT_EQ(run("info cornell --log error").exit_code, 0);
}

// A bake folder of the wrong kind is refused with one line saying what the command takes.
TEST_F(CliAppBinary, BakedFolderOfAnotherKind) {
  const fs::path lm = dir_ / "lm", prt = dir_ / "prt";
  ASSERT_EQ(run("bake cornell --resolution 32 --spp 1 -o " + lm.string()).exit_code, 0);
  ASSERT_EQ(run("bake cornell --kind prt --resolution 32 --spp 1 -o " + prt.string()).exit_code, 0);
  expect_bad_input(
      run("export cornell --baked " + prt.string() + " -o " + (dir_ / "x.glb").string()),
      "a PRT folder; illum export takes a light-map folder");
  expect_bad_input(run("relight cornell --baked " + lm.string() + " --sun 0,-1,0 -o " +
                       (dir_ / "x.png").string()),
                   "a light-map folder; illum relight takes a PRT folder");
  EXPECT_FALSE(fs::exists(dir_ / "x.glb"));
  EXPECT_FALSE(fs::exists(dir_ / "x.png"));
}

// With stderr a file, long work reports in plain lines at the interval (shortened here by
// ILLUM_PROGRESS_INTERVAL): no carriage return, an end line, and stdout untouched.
TEST_F(CliAppBinary, ProgressLinesWhenStderrIsAFile) {
  const Result r = run_command("ILLUM_PROGRESS_INTERVAL=0.001 " + std::string(ILLUM_BINARY_DIR) +
                               "/bin/illum render cornell -i path --width 64 --height 64 "
                               "--spp 16 --threads 1 -o " +
                               (dir_ / "x.png").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find('\r'), std::string::npos) << r.err;
  EXPECT_TRUE(std::regex_search(r.err, std::regex(R"((^|\n)path: [0-9]+% \()"))) << r.err;
  EXPECT_TRUE(std::regex_search(r.err, std::regex(R"(\npath: 100% in )"))) << r.err;
  // The default interval (5 s) prints nothing for a run this short.
  const Result quiet =
      run("render cornell -i path --width 16 --height 16 --spp 1 -o " + (dir_ / "y.png").string());
  ASSERT_EQ(quiet.exit_code, 0) << quiet.err;
  EXPECT_EQ(quiet.err.find('%'), std::string::npos) << quiet.err;
#ifdef ILLUM_HAVE_GPU
  const Result f = run_command("ILLUM_PROGRESS_INTERVAL=0.001 " + std::string(ILLUM_BINARY_DIR) +
                               "/bin/illum frame cornell --width 16 --height 16 --frames 20");
  ASSERT_EQ(f.exit_code, 0) << f.err;
  EXPECT_EQ(f.err.find('\r'), std::string::npos) << f.err;
  EXPECT_TRUE(std::regex_search(f.err, std::regex(R"((^|\n)frame: [0-9]+% \()"))) << f.err;
  EXPECT_EQ(f.out.find('%'), std::string::npos) << "progress went to stdout: " << f.out;
#endif
}

}  // namespace

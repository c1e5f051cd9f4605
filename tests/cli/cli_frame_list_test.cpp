// `illum frame --list` and the technique options of `illum frame` / `illum view`: the list
// names every technique of the registry (compared with realtime/technique_registry.h itself)
// with its parameters, needs no scene and no Vulkan; an unknown technique, parameter or
// value, and --enable of an exclusive technique, exit 2 with one line naming it; the short
// keys of before the technique interface still work.
#ifdef ILLUM_HAVE_GPU

#include <nlohmann/json.hpp>

#include "cli_fixture.h"
#include "illum/realtime/technique_registry.h"

using namespace illum_cli_test;
namespace rt = illum::realtime;

namespace {

class CliFrameListTest : public CliTest {
 protected:
  void SetUp() override {
    CliTest::SetUp();
    ::unsetenv("DISPLAY");  // `illum view` renders headless here
    ::unsetenv("WAYLAND_DISPLAY");
  }
  std::string frame(const std::string& extra) {
    return "frame cornell --width 8 --height 8 -o " + (dir_ / "f.png").string() + " " + extra;
  }
  std::string view(const std::string& extra) {
    return "view cornell --width 8 --height 8 --close-after-frames 1 --fallback-output " +
           (dir_ / "v.png").string() + " " + extra;
  }
  // Bad input: exit 2, one line naming `needle`, no image written.
  void refused(const std::string& args, const std::string& needle) {
    SCOPED_TRACE("illum " + args);
    expect_bad_input(run(args), needle);
    EXPECT_FALSE(fs::exists(dir_ / "f.png"));
    EXPECT_FALSE(fs::exists(dir_ / "v.png"));
  }
  // The passes `illum frame ARGS --json` timed.
  std::vector<std::string> passes(const std::string& args) {
    const fs::path json = dir_ / "t.json";
    const Result r = run(frame(args + " --json " + json.string()));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    std::vector<std::string> names;
    if (r.exit_code != 0) return names;
    const nlohmann::json timings = nlohmann::json::parse(slurp(json));
    for (const auto& p : timings["passes"]) names.push_back(p["name"].get<std::string>());
    fs::remove(json);
    fs::remove(dir_ / "f.png");
    return names;
  }
};

bool contains(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

// A technique's own line in the text list: "  NAME: summary" or "  NAME (on by default)...".
bool listed(const std::string& out, const std::string& name) {
  return out.find("\n  " + name + ": ") != std::string::npos ||
         out.find("\n  " + name + " (") != std::string::npos;
}

// Runs `body` with the Vulkan loader pointed at no driver at all.
template <typename F>
void without_vulkan_driver(F body) {
  ::setenv("VK_ICD_FILENAMES", "/nonexistent/icd.json", 1);
  ::setenv("VK_DRIVER_FILES", "/nonexistent/icd.json", 1);
  body();
  ::unsetenv("VK_ICD_FILENAMES");
  ::unsetenv("VK_DRIVER_FILES");
}

// Every registered technique and parameter is listed, from the registry's own list.
TEST_F(CliFrameListTest, ListNamesEveryRegisteredTechniqueAndParameter) {
  // No Vulkan driver at all (a frame then fails: the environment does hide the driver) and
  // no scene: the list needs neither.
  Result r, frame_without_driver;
  without_vulkan_driver([&] {
    r = run("frame --list");
    frame_without_driver = run(frame(""));
  });
  EXPECT_EQ(frame_without_driver.exit_code, 2) << frame_without_driver.err;
  EXPECT_NE(frame_without_driver.err.find("Vulkan"), std::string::npos) << frame_without_driver.err;
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  size_t techniques = 0, params = 0;
  for (const rt::TechniqueDecl& t : rt::technique_registry()) {
    ++techniques;
    EXPECT_TRUE(listed(r.out, t.name)) << t.name;
    for (const rt::ParamDecl& p : t.params) {
      ++params;
      const std::string line = "\n    " + t.name + "." + p.key + "  " + rt::type_name(p.type);
      EXPECT_NE(r.out.find(line), std::string::npos) << t.name << "." << p.key;
      EXPECT_NE(r.out.find(p.help), std::string::npos) << t.name << "." << p.key;
    }
  }
  // The registry holds what this issue moved onto it (and more may come).
  EXPECT_GE(techniques, 11u);
  EXPECT_GE(params, 20u);
  // A few known entries with their type, range, default and kind of change.
  for (const char* known : {
           "    map.pcf_taps  int [1, 64]  default 16  per-frame  [pcf_taps]",
           "    map.resolution  int [16, 8192]  default 512  structural  [shadow_resolution]",
           "    vsm.tau  float [0, 0.99]  default 0.2  per-frame  [vsm_tau]",
           "    deferred.lighting  enum compute|volumes  default compute  structural",
           "    tonemap.operator  enum clamp|reinhard|aces|agx  default aces  per-frame",
           "    volume.silhouettes  enum gpu|cpu  default gpu  structural  [silhouettes]",
           "    bloom.strength  float [0, 100]  default 0.5  per-frame  [bloom_strength]",
           "  bloom (off by default)",
           "  luminance (on by default) [-p auto_exposure=true|false]",
           "  tonemap (on by default)",
       })
    EXPECT_NE(r.out.find(known), std::string::npos) << known;
}

TEST_F(CliFrameListTest, ListAsJsonMatchesTheRegistry) {
  const Result r = run("frame --list --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  const auto& list = j.at("techniques");
  const auto& registry = rt::technique_registry();
  ASSERT_EQ(list.size(), registry.size());
  for (size_t i = 0; i < registry.size(); ++i) {
    const rt::TechniqueDecl& t = registry[i];
    EXPECT_EQ(list[i]["name"], t.name);
    EXPECT_EQ(list[i]["kind"], rt::kind_name(t.kind));
    ASSERT_EQ(list[i]["params"].size(), t.params.size()) << t.name;
    for (size_t k = 0; k < t.params.size(); ++k) {
      const auto& p = list[i]["params"][k];
      EXPECT_EQ(p["name"], t.name + "." + t.params[k].key);
      EXPECT_EQ(p["type"], rt::type_name(t.params[k].type));
      EXPECT_EQ(p["help"], t.params[k].help);
    }
  }
  auto param = [&](const std::string& name) {
    for (const auto& t : list)
      for (const auto& p : t["params"])
        if (p["name"] == name) return p;
    ADD_FAILURE() << name << " not listed";
    return nlohmann::json();
  };
  EXPECT_EQ(param("map.pcf_taps")["default"], 16);
  EXPECT_EQ(param("map.pcf_taps")["min"], 1);
  EXPECT_EQ(param("map.pcf_taps")["max"], 64);
  EXPECT_EQ(param("map.pcf_taps")["change"], "per-frame");
  EXPECT_EQ(param("map.pcf_taps")["alias"], "pcf_taps");
  EXPECT_EQ(param("tonemap.exposure")["default"], 1.0);
  EXPECT_EQ(param("lighting.ambient")["default"], nlohmann::json::array({0.0, 0.0, 0.0}));
  EXPECT_EQ(param("deferred.lighting")["values"], nlohmann::json::array({"compute", "volumes"}));
  EXPECT_EQ(param("deferred.lighting")["change"], "structural");
  // --json FILE writes the same to the file.
  const fs::path file = dir_ / "techniques.json";
  ASSERT_EQ(run("frame --list --json " + file.string()).exit_code, 0);
  EXPECT_EQ(nlohmann::json::parse(slurp(file)), j);
}

TEST_F(CliFrameListTest, UnknownTechniquesParametersAndValuesExit2WithOneLine) {
  for (const bool in_view : {false, true}) {
    auto with = [&](const std::string& extra) { return in_view ? view(extra) : frame(extra); };
    refused(with("--technique raytraced"), "raytraced");
    refused(with("--shadows penumbra"), "penumbra");
    refused(with("--enable sparkles"), "sparkles");
    refused(with("--enable bloom,sparkles"), "sparkles");
    refused(with("--disable sparkles"), "sparkles");
    // The exclusive kinds are chosen by name, not switched.
    refused(with("--enable deferred"), "frame pipeline, chosen with --technique");
    refused(with("--enable vsm"), "shadow method, chosen with --shadows");
    refused(with("--disable map"), "shadow method, chosen with --shadows");
    refused(with("--enable lighting"), "always on");
    refused(with("--enable bloom --disable bloom"), "contradict");
    // Unknown parameters: a short key, a technique, a key of a known technique.
    refused(with("-p pcf_tapz=8"), "pcf_tapz");
    refused(with("-p sparkles.amount=1"), "no technique 'sparkles'");
    refused(with("-p map.tapz=8"), "technique 'map' has no parameter 'tapz'");
    // Values of the wrong type, out of range, or not one of the declared values.
    refused(with("-p map.pcf_taps=0"), "map.pcf_taps");
    refused(with("-p pcf_taps=65"), "map.pcf_taps");
    refused(with("-p map.pcf_taps=many"), "map.pcf_taps");
    refused(with("-p deferred.lighting=raymarched"), "deferred.lighting");
    refused(with("-p silhouettes=fpga"), "volume.silhouettes");
    refused(with("-p lighting.ambient=[1,2]"), "lighting.ambient");
    refused(with("-p ambient=[-1,0,0]"), "lighting.ambient");
    refused(with("-p bloom.strength=1e9"), "bloom.strength");
    refused(with("-p auto_exposure=2"), "auto_exposure");
    // Parameters a dedicated option sets.
    refused(with("-p tonemap.operator=agx"), "--tonemap");
    refused(with("-p tonemap.exposure=2"), "--exposure");
    refused(with("--fixed-exposure --enable luminance"), "--fixed-exposure");
  }
  refused("frame -o " + (dir_ / "f.png").string(), "scene is required");
  refused("frame cornell --json -o " + (dir_ / "f.png").string(), "--json");
  refused("frame cornell --list", "--list");
}

// The keys from before the technique interface (and the add-on switches) reach the frame.
TEST_F(CliFrameListTest, AddOnsSwitchAndShortKeysStillWork) {
  const std::vector<std::string> plain = passes("");
  EXPECT_TRUE(contains(plain, "luminance"));
  EXPECT_TRUE(contains(plain, "tonemap"));
  EXPECT_FALSE(contains(plain, "bloom"));
  EXPECT_TRUE(contains(passes("--enable bloom"), "bloom"));
  EXPECT_TRUE(contains(passes("-p bloom_strength=0.5 -p bloom_threshold=2"), "bloom"));
  EXPECT_FALSE(contains(passes("-p bloom_strength=0"), "bloom"));
  // bloom_strength=0 switches bloom off, as before the technique interface: against
  // --enable bloom that is a contradiction.
  refused(frame("--enable bloom -p bloom_strength=0"), "contradicts");
  refused(frame("--disable luminance -p auto_exposure=true"), "contradicts");
  EXPECT_FALSE(contains(passes("--disable luminance"), "luminance"));
  EXPECT_FALSE(contains(passes("--fixed-exposure"), "luminance"));
  EXPECT_FALSE(contains(passes("-p auto_exposure=false"), "luminance"));
  const std::vector<std::string> deferred = passes(
      "--technique deferred -p deferred_lighting=volumes -p pcf_taps=4 -p "
      "shadow_resolution=64 -p half_lambert=true -p vsm_tau=0.5");
  EXPECT_TRUE(contains(deferred, "gbuffer"));
  EXPECT_TRUE(contains(deferred, "lighting"));
  EXPECT_TRUE(contains(passes("--shadows volume -p silhouettes=cpu -p volume_back_faces=true"),
                       "cpu:silhouettes"));
  // Disabling the tone mapper leaves nothing to write the 8-bit output.
  refused(frame("--disable tonemap"), "tonemap");
  const Result v = run(view("--enable bloom -p map.pcf_taps=4 -p bloom.threshold=2"));
  EXPECT_EQ(v.exit_code, 0) << v.err;
}

}  // namespace

#endif

// --sun and --sky on every command that lights a scene, and the one sentence for a scene
// without light: render and a path-traced light-map warn (exit 0), the radiosity and probe
// bakes refuse (exit 2), all naming --sun and --sky; with a sun added, the same scene lights.
#include <nlohmann/json.hpp>

#include "cli_fixture.h"
#include "illum/core/image.h"

using namespace illum_cli_test;

namespace {

class LightingCli : public CliTest {
 protected:
  // A floor quad facing +z and nothing else: no lamp, no emitter, no environment.
  std::string unlit() { return quad_gltf("floor", {R"({"mesh": 0})"}); }
};

double mean_of(const fs::path& exr) {
  const illum::Image image = illum::read_image(exr.string(), false);
  double sum = 0.0;
  for (float v : image.data()) sum += v;
  return sum / double(image.data().size());
}

TEST_F(LightingCli, UnlitSceneIsTheSameSentenceEverywhere) {
  const std::string scene = unlit();
  const Result render =
      run("render " + scene + " --width 8 --height 8 --spp 1 -o " + (dir_ / "r.exr").string());
  EXPECT_EQ(render.exit_code, 0) << render.err;
  const Result bake =
      run("bake " + scene + " --resolution 16 --spp 1 -o " + (dir_ / "lm").string());
  EXPECT_EQ(bake.exit_code, 0) << bake.err;
  for (const Result* r : {&render, &bake})
    for (const char* part : {"has no light", "--sun", "--sky"})
      EXPECT_NE(r->err.find(part), std::string::npos) << r->err;
  for (const std::string kind : {"--method radiosity --resolution 16", "--kind probes"}) {
    const Result r = run("bake " + scene + " " + kind + " -o " + (dir_ / "refused").string());
    expect_bad_input(r, "has no light");
    EXPECT_NE(r.err.find("--sun"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "refused"));
  }
}

TEST_F(LightingCli, SunAndSkyLightTheScene) {
  const std::string scene = unlit();
  // The quad faces +z: a sun travelling along −z at E = π lights it to radiance ρ (the
  // default material's albedo) where it is seen; a sky of radiance 1 alike.
  for (const std::string light :
       {"--sun 0,0,-1", "--sun 0,0,-1,3.14159", "--sky 1", "--sky 1,1,1"}) {
    const fs::path out = dir_ / "lit.exr";
    const Result r =
        run("render " + scene + " " + light + " --width 8 --height 8 --spp 4 -o " + out.string());
    ASSERT_EQ(r.exit_code, 0) << light << ": " << r.err;
    EXPECT_EQ(r.err.find("has no light"), std::string::npos) << r.err;
    EXPECT_GT(mean_of(out), 0.01) << light;
  }
  const Result baked =
      run("bake " + scene + " --sun 0,0,-1 --method radiosity --resolution 16 -o " +
          (dir_ / "lm").string());
  EXPECT_EQ(baked.exit_code, 0) << baked.err;
  for (const std::string bad : {"--sun 0,0,0", "--sun 1,2", "--sky -1", "--sky missing.hdr"})
    expect_bad_input(run("render " + scene + " " + bad + " -o " + (dir_ / "x.png").string()),
                     bad.substr(0, 5));
}

TEST_F(LightingCli, PrtBakeTakesNoLight) {
  expect_bad_input(run("bake cornell --kind prt --sun 0,-1,0 -o " + (dir_ / "p").string()),
                   "illum relight");
}

#ifdef ILLUM_HAVE_GPU  // `illum frame` exists only with the GPU layers
TEST_F(LightingCli, RealTimeSaysItDoesNotShowTheSky) {
  const Result r =
      run("frame " + unlit() + " --sky 1 --width 8 --height 8 -o " + (dir_ / "f.png").string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("does not light with an environment"), std::string::npos) << r.err;
  const Result sun = run("frame " + unlit() + " --sun 0,0,-1 --width 8 --height 8 -o " +
                         (dir_ / "s.png").string());
  EXPECT_EQ(sun.exit_code, 0) << sun.err;
  EXPECT_EQ(sun.err.find("has no light"), std::string::npos) << sun.err;
}
#endif

}  // namespace

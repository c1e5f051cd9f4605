// The .glb of `illum export` read back by illum itself: `illum info` reports its light-map,
// and `illum frame` shows it with no other option — the same frame as the bake folder it was
// exported from, within what RGBM's 8 bits and the half floats on the way allow, and far from
// the frame without it. Every basis the exporter takes reads back; a tone-mapped map (display
// values, not light) is refused with one line.
#include <cmath>

#include <nlohmann/json.hpp>

#include "cli_fixture.h"
#include "illum/core/image.h"

namespace illum_cli_test {
namespace {

class ExportReadbackCli : public CliTest {
 protected:
  fs::path bake(const std::string& name, const std::string& extra) {
    const fs::path folder = dir_ / name;
    const Result r =
        run("bake cornell --resolution 32 --seed 1 " + extra + " -o " + folder.string());
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return folder;
  }
  fs::path do_export(const fs::path& folder, const std::string& name,
                     const std::string& extra = "") {
    const fs::path glb = dir_ / name;
    const Result r =
        run("export cornell --baked " + folder.string() + " -o " + glb.string() + " " + extra);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return glb;
  }
  nlohmann::json info(const fs::path& scene) {
    const Result r = run("info " + scene.string() + " --json");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return nlohmann::json::parse(r.out, nullptr, false);
  }
};

TEST_F(ExportReadbackCli, InfoReportsTheLightmap) {
  const fs::path glb = do_export(bake("lm", "--spp 1"), "e.glb");
  const nlohmann::json j = info(glb);
  ASSERT_TRUE(j.contains("lightmap")) << j.dump();
  EXPECT_EQ(j.at("textures"), 1);  // the Cornell box has no material textures
  const nlohmann::json& m = j.at("lightmap");
  EXPECT_EQ(m.at("encoding"), "RGBM");
  EXPECT_EQ(m.at("basis"), "plain");
  EXPECT_EQ(m.at("tone"), "none");
  EXPECT_EQ(m.at("width"), 32);
  EXPECT_EQ(m.at("height"), 32);
  EXPECT_GT(m.at("range").get<double>(), 0.0);
  const Result text = run("info " + glb.string());
  EXPECT_NE(text.out.find("light-map   32x32 RGBM"), std::string::npos) << text.out;
  // A scene without one reports none.
  const nlohmann::json plain = info(fs::path("cornell"));
  EXPECT_FALSE(plain.contains("lightmap"));
  EXPECT_EQ(plain.at("textures"), 0);
}

// MSFT_lightmap as other tools write it (no RGBM extras, or another texture coordinate) is
// not illum's encoding: one warning, the scene loads without a light-map.
TEST_F(ExportReadbackCli, OtherLightmapsLoadWithoutTheirMapAndOneWarning) {
  illum::write_image((dir_ / "lm.png").string(), illum::Image(2, 2, 4, 0.5f));
  const auto with_lightmap = [&](const std::string& name, const nlohmann::json& extension) {
    const fs::path gltf = quad_gltf(name, {R"({"mesh": 0})"});
    nlohmann::json j = nlohmann::json::parse(slurp(gltf));
    j["meshes"][0]["primitives"][0]["material"] = 0;
    j["materials"] = {{{"extensions", {{"MSFT_lightmap", extension}}}}};
    j["textures"] = {{{"source", 0}}};
    j["images"] = {{{"uri", "lm.png"}}};
    write(name + ".gltf", j.dump());
    return info(gltf);
  };
  const nlohmann::json texture = {{"index", 0}, {"texCoord", 1}};
  const nlohmann::json rgbm = {{"encoding", "RGBM"}, {"range", 2.0}, {"tone", "none"}};
  const struct {
    nlohmann::json extension;
    const char* warning;
  } cases[] = {
      {{{"lightmapTexture", texture}}, "no extras.encoding"},
      {{{"lightmapTexture", {{"index", 0}}}, {"extras", rgbm}}, "texCoord 0"},
      {{{"lightmapTexture", {{"index", 3}, {"texCoord", 1}}}, {"extras", rgbm}},
       "names no texture"},
      {{{"lightmapTexture", texture}, {"extras", {{"encoding", "RGBM"}, {"range", -1}}}},
       "extras.range"},
  };
  for (const auto& c : cases) {
    const nlohmann::json j = with_lightmap("other", c.extension);
    EXPECT_FALSE(j.contains("lightmap")) << c.warning;
    ASSERT_EQ(j.at("warnings").size(), 1u) << j.dump();
    EXPECT_NE(j.at("warnings")[0].get<std::string>().find(c.warning), std::string::npos)
        << j.at("warnings")[0];
  }
  // With illum's extras the same file carries a 2×2 light-map: 0.5·0.5·2 everywhere.
  const nlohmann::json own = with_lightmap("own", {{"lightmapTexture", texture}, {"extras", rgbm}});
  ASSERT_TRUE(own.contains("lightmap")) << own.dump();
  EXPECT_EQ(own.at("lightmap").at("width"), 2);
}

#ifdef ILLUM_HAVE_GPU

constexpr int kSize = 64;

struct Means {
  double c[3] = {0, 0, 0};
};
Means means(const illum::Image& image) {
  Means m;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x)
      for (int c = 0; c < 3; ++c) m.c[c] += image.pixel(x, y)[c];
  for (double& v : m.c) v /= static_cast<double>(image.pixel_count());
  return m;
}

TEST_F(ExportReadbackCli, FrameShowsTheLightmapAsTheBakeFolderDoes) {
  const fs::path folder = bake("lm", "--spp 4");
  const fs::path glb = do_export(folder, "e.glb");
  const std::string size =
      " --width " + std::to_string(kSize) + " --height " + std::to_string(kSize) + " -o ";
  const fs::path from_glb = dir_ / "glb.exr", from_folder = dir_ / "folder.exr",
                 unlit = dir_ / "unlit.exr";
  Result r = run("frame " + glb.string() + size + from_glb.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run("frame cornell --baked " + folder.string() + size + from_folder.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run("frame cornell" + size + unlit.string());  // the same scene, no light-map
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const illum::Image a = illum::read_image(from_glb.string(), false);
  const illum::Image b = illum::read_image(from_folder.string(), false);
  const illum::Image u = illum::read_image(unlit.string(), false);
  ASSERT_EQ(a.width(), b.width());
  ASSERT_EQ(a.height(), b.height());

  // The bound. Both frames show albedo × bilinear(map) (+ emission) on the same geometry:
  // the folder's map in float, the file's decoded from RGBM, each texel within half an 8-bit
  // step at its multiplier, at most 0.5/255·(1 + 1/255)·M (docs/lightmap-export.md). Bilinear
  // weights are convex and albedo ≤ 1, so a pixel differs by at most that, plus the half
  // floats the map is uploaded in and the EXR is written in (2^-11 relative each, on both
  // sides: 2^-9 of the value).
  const double range = info(glb).at("lightmap").at("range").get<double>();
  const double rgbm = 0.5 / 255.0 * (1.0 + 1.0 / 255.0) * range;
  const double half = std::ldexp(1.0, -9);
  const Means ma = means(a), mb = means(b), mu = means(u);
  int outside = 0;
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x)
      for (int c = 0; c < 3; ++c) {
        const double va = a.pixel(x, y)[c], vb = b.pixel(x, y)[c];
        outside += std::abs(va - vb) > rgbm + half * std::max(std::abs(va), std::abs(vb));
      }
  double far = 0.0, tolerance_sum = 0.0;
  for (int c = 0; c < 3; ++c) {
    const double tolerance = rgbm + half * mb.c[c];
    std::printf("channel %d: mean %.6f (glb) %.6f (folder) %.6f (no light-map), tolerance %.6f\n",
                c, ma.c[c], mb.c[c], mu.c[c], tolerance);
    EXPECT_LE(std::abs(ma.c[c] - mb.c[c]), tolerance) << "channel " << c;
    far += std::abs(ma.c[c] - mu.c[c]);
    tolerance_sum += tolerance;
  }
  // Pixels on an edge may differ (the glTF camera's matrix is rebuilt from floats): 1 in 100.
  EXPECT_LE(outside, a.pixel_count() * 3 / 100) << outside << " pixel channels outside the bound";
  // The light-map matters: without it the frame is far outside the tolerance.
  EXPECT_GT(far, 4.0 * tolerance_sum) << "the .glb frame is as close to the unlit frame";
}

// `illum view` (its headless fallback) goes the same way: the .glb's picture is the bake
// folder's, not the unlit scene's. 8-bit PNGs under auto exposure, so the check is relative:
// ten times closer to the folder's picture than to the unlit one, per channel mean.
TEST_F(ExportReadbackCli, ViewShowsTheLightmap) {
  const fs::path folder = bake("lm", "--spp 4");
  const fs::path glb = do_export(folder, "e.glb");
  const auto view = [&](const std::string& scene, const std::string& name) {
    const fs::path out = dir_ / name;
    const Result r =
        run("view " + scene + " --close-after-frames 1 --fallback-output " + out.string());
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return means(illum::read_image(out.string(), true));
  };
  const Means g = view(glb.string(), "glb.png");
  const Means f = view("cornell --baked " + folder.string(), "folder.png");
  const Means u = view("cornell", "unlit.png");
  for (int c = 0; c < 3; ++c)
    EXPECT_LT(10.0 * std::abs(g.c[c] - f.c[c]), std::abs(g.c[c] - u.c[c]))
        << "channel " << c << ": " << g.c[c] << " (glb) " << f.c[c] << " (folder) " << u.c[c]
        << " (unlit)";
}

TEST_F(ExportReadbackCli, EveryExportedBasisReadsBackAndToneMappedMapsAreRefused) {
  for (const std::string basis : {"plain", "rnm", "sh", "dominant"}) {
    const fs::path glb = do_export(bake(basis, "--spp 1 --basis " + basis), basis + ".glb");
    EXPECT_EQ(info(glb).at("lightmap").at("basis"), basis);
    const Result r =
        run("frame " + glb.string() + " --width 16 --height 16 -o " + (dir_ / "f.png").string());
    EXPECT_EQ(r.exit_code, 0) << basis << ": " << r.err;
  }
  const fs::path toned = do_export(dir_ / "plain", "toned.glb", "--tone lrp97");
  EXPECT_EQ(info(toned).at("lightmap").at("tone"), "lrp97");
  const fs::path out = dir_ / "toned.png";
  expect_bad_input(run("frame " + toned.string() + " -o " + out.string()), "--tone none");
  EXPECT_FALSE(fs::exists(out));
}

#endif  // ILLUM_HAVE_GPU

}  // namespace
}  // namespace illum_cli_test

// Bake identity: a light-map folder records the geometry_hash of
// the scene it was baked for (scene/geometry_hash.h: positions, normals, tangents, indices,
// transforms, and the atlas's uv1), and `illum frame` / `illum view` refuse a folder baked
// for another scene — or one that records no hash — with one line and exit 2, before any
// rendering or window.
#include <cstdint>
#include <regex>

#include "cli_fixture.h"

namespace {

using illum_cli_test::CliTest;
using illum_cli_test::Result;
using illum_cli_test::slurp;

#ifdef ILLUM_HAVE_GPU

class BakeIdentity : public CliTest {
 protected:
  Result bake(const std::string& scene, const fs::path& folder, const std::string& extra = "") {
    return run("bake " + scene + " --resolution 32 --spp 1 --seed 1 " + extra + " -o " +
               folder.string());
  }
  Result frame(const std::string& scene, const fs::path& folder) {
    return run("frame " + scene + " --baked " + folder.string() + " --width 16 --height 16 -o " +
               (dir_ / "frame.png").string());
  }
  Result view(const std::string& scene, const fs::path& folder) {
    return run("view " + scene + " --baked " + folder.string() +
               " --close-after-frames 1 --fallback-output " + (dir_ / "view.png").string());
  }
  std::string recorded_hash(const fs::path& folder) {
    std::smatch m;
    const std::string manifest = slurp(folder / "lightmap.json");
    return std::regex_search(manifest, m, std::regex("\"scene_hash\": \"([0-9a-f]*)\""))
               ? m[1].str()
               : "";
  }
};

TEST_F(BakeIdentity, BakeRecordsTheHashAndTheSameGeometryIsAccepted) {
  const fs::path lm = dir_ / "lm";
  ASSERT_EQ(bake("cornell", lm).exit_code, 0);
  EXPECT_EQ(recorded_hash(lm).size(), 16u) << slurp(lm / "lightmap.json");
  const Result same = frame("cornell", lm);
  EXPECT_EQ(same.exit_code, 0) << same.err;
  // The same geometry under another name and file is the same scene (names are not hashed).
  const Result copy = frame(cornell_copy("copy", ""), lm);
  EXPECT_EQ(copy.exit_code, 0) << copy.err;
  // Baking the same scene again records the same hash (deterministic, thread-independent).
  const fs::path again = dir_ / "again";
  ASSERT_EQ(bake(cornell_copy("copy", ""), again, "--threads 1").exit_code, 0);
  EXPECT_EQ(recorded_hash(again), recorded_hash(lm));
}

// Same triangle count, one instance moved by 1 mm: the count check passes, the hash refuses.
TEST_F(BakeIdentity, AnotherTransformIsAnotherScene) {
  const fs::path lm = dir_ / "lm";
  ASSERT_EQ(bake("cornell", lm).exit_code, 0);
  const std::string moved = cornell_copy("moved", "{\"translate\": [0, 0.001, 0]}");
  expect_bad_input(frame(moved, lm), "bake it again for this scene");
  expect_bad_input(view(moved, lm), "bake it again for this scene");
  EXPECT_FALSE(fs::exists(dir_ / "frame.png"));
  EXPECT_FALSE(fs::exists(dir_ / "view.png"));
}

// glTF keeps node transforms as instance transforms (the .illum.json loader above bakes a
// mesh's transform into its vertices): two instances of one quad, the second moved 1 mm.
TEST_F(BakeIdentity, AnotherInstanceTransformIsAnotherScene) {
  const auto gltf = [&](const std::string& name, const std::string& translation) {
    return quad_gltf(name,
                     {R"({"mesh": 0})", R"({"mesh": 0, "translation": )" + translation + "}"});
  };
  const std::string a = gltf("a", "[2, 0, 0]"), b = gltf("b", "[2, 0, 0.001]");
  const fs::path lm = dir_ / "lm";
  const Result baked = bake(a, lm);
  ASSERT_EQ(baked.exit_code, 0) << baked.err;
  const Result same = frame(a, lm);
  EXPECT_EQ(same.exit_code, 0) << same.err;
  expect_bad_input(frame(b, lm), "baked for another scene than 'b'");
}

// Same triangle count and transforms, one vertex moved.
TEST_F(BakeIdentity, OtherPositionsAreAnotherScene) {
  const std::string quad = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n";
  write("a.obj", quad);
  std::string bent = quad;
  bent.replace(bent.find("v 1 1 0"), 7, "v 1 1.01 0");
  write("b.obj", bent);
  const fs::path lm = dir_ / "lm";
  const Result baked = bake((dir_ / "a.obj").string(), lm);
  ASSERT_EQ(baked.exit_code, 0) << baked.err;
  const Result same = frame((dir_ / "a.obj").string(), lm);
  EXPECT_EQ(same.exit_code, 0) << same.err;
  expect_bad_input(frame((dir_ / "b.obj").string(), lm), "baked for another scene than 'b'");
}

// The atlas is part of the identity: atlas.bin of another bake of the same scene (same size
// and chart count, other padding, so the manifest's own checks pass) is refused.
TEST_F(BakeIdentity, AnAtlasFromAnotherBakeIsRefused) {
  const fs::path lm = dir_ / "lm", other = dir_ / "other";
  ASSERT_EQ(bake("cornell", lm).exit_code, 0);
  ASSERT_EQ(bake("cornell", other, "-p padding=3").exit_code, 0);
  ASSERT_NE(slurp(lm / "atlas.bin"), slurp(other / "atlas.bin"));
  fs::copy_file(other / "atlas.bin", lm / "atlas.bin", fs::copy_options::overwrite_existing);
  expect_bad_input(frame("cornell", lm), "bake it again");
}

// A folder from before the hash (no "scene_hash"): refused, saying to bake again; a
// malformed hash is a manifest error naming the key.
TEST_F(BakeIdentity, FoldersWithoutOrWithABadHashAreRefused) {
  const fs::path lm = dir_ / "lm";
  ASSERT_EQ(bake("cornell", lm).exit_code, 0);
  const std::string manifest = slurp(lm / "lightmap.json");
  const std::string line = "\"scene_hash\": \"" + recorded_hash(lm) + "\",";
  const size_t at = manifest.find(line);
  ASSERT_NE(at, std::string::npos) << manifest;
  std::string old = manifest;
  write("lm/lightmap.json", old.erase(at, line.size()));
  expect_bad_input(frame("cornell", lm), "records no scene hash (baked by an earlier illum)");
  expect_bad_input(view("cornell", lm), "bake it again");
  std::string bad = manifest;
  write("lm/lightmap.json", bad.replace(at, line.size(), "\"scene_hash\": \"XYZ\","));
  expect_bad_input(frame("cornell", lm), "'scene_hash' must be 16 lowercase hex digits");
  std::string flipped = manifest;
  const size_t digit = at + std::string("\"scene_hash\": \"").size();
  flipped[digit] = flipped[digit] == '0' ? '1' : '0';
  write("lm/lightmap.json", flipped);
  expect_bad_input(frame("cornell", lm), "bake it again for this scene");
  EXPECT_FALSE(fs::exists(dir_ / "frame.png"));
}

#endif

}  // namespace

// The loops that `mpirun` splits across ranks (core/work_split.h; distributed/README.md):
// render tiles, light-map texels and the extra maps' texels give the same floats, bit for
// bit, whether they run in one process or are handed out in units to several ranks. An
// in-process split stands in for MPI: it hands out units of uneven sizes in shuffled order
// (as ranks of different speeds would ask for them), computes each on this process and
// passes the records through bytes to the root's `keep`, as MpiJob does. The CLI tests
// (tests/cli/mpi_cli_test.cpp) run the real MPI protocol but compare files, whose half
// floats would hide a change in the last bits of a sum.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <random>
#include <vector>

#include "charted_cornell.h"
#include "illum/atlas/atlas.h"
#include "illum/atlas/texel_raster.h"
#include "illum/bake/lightmap_baker.h"
#include "illum/bake/lightmap_extras.h"
#include "illum/core/error.h"
#include "illum/core/params.h"
#include "illum/core/work_split.h"
#include "illum/render/integrator.h"
#include "illum/scene/load.h"
#include "illum/trace/ray_tracer.h"

namespace illum {
namespace {

// Several "ranks" in this process: every unit is computed here, in a shuffled order.
class ShuffledSplit final : public WorkSplit {
 public:
  explicit ShuffledSplit(int ranks) : ranks_(ranks) {}
  int ranks() const override { return ranks_; }
  int rank() const override { return 0; }
  int threads_per_rank() const override { return 1; }
  void run(int64_t count, size_t record_bytes, int grain, const UnitWork& work,
           const UnitKeep& keep) override {
    ++runs;
    std::mt19937 rng(12345u + static_cast<unsigned>(runs));
    std::vector<std::pair<int64_t, int64_t>> units;
    for (int64_t begin = 0; begin < count;) {
      const int64_t n = std::min<int64_t>(count - begin, 1 + rng() % (3 * grain));
      units.emplace_back(begin, begin + n);
      begin += n;
    }
    std::shuffle(units.begin(), units.end(), rng);
    for (const auto& [begin, end] : units) {
      std::vector<std::byte> records(static_cast<size_t>(end - begin) * record_bytes);
      work(begin, end, records.data());
      const std::vector<std::byte> sent = records;  // what the network would deliver
      keep(begin, end, sent.data());
    }
  }
  int runs = 0;

 private:
  int ranks_;
};

bool identical_bytes(const Image& a, const Image& b) {
  return a.width() == b.width() && a.height() == b.height() && a.channels() == b.channels() &&
         std::memcmp(a.data().data(), b.data().data(), a.data().size() * sizeof(float)) == 0;
}

Image render(const std::string& integrator, const Scene& scene, const RayTracer& tracer, int spp) {
  RenderOptions o;
  o.width = 40;  // 3×3 tiles, the last row and column cut
  o.height = 36;
  o.spp = spp;
  o.seed = 9;
  o.progress = false;
  nlohmann::json p = nlohmann::json::object();
  if (integrator == "photon") p = {{"photons", 5000}, {"caustic_photons", 5000}, {"k", 20}};
  const Camera camera = scene.camera ? *scene.camera : Camera::framing(scene.bounds());
  return Integrator::create(integrator, Params(p, "--param"))->render(tracer, camera, o);
}

TEST(SplitLoops, RenderTilesGiveTheSameFloatsAsOneProcess) {
  const Scene scene = load_scene("cornell");
  const RayTracer tracer(scene);
  // 24 spp: passes of 1, 1, 2, 4, 8, 8, which a tile sent to another rank must repeat.
  for (const std::string name : {"path", "whitted", "ao", "photon"}) {
    const Image one = render(name, scene, tracer, 24);
    ShuffledSplit split(3);
    const ScopedWorkSplit installed(&split);
    const Image split_image = render(name, scene, tracer, 24);
    EXPECT_EQ(split.runs, 1) << name << ": the tiles were not split";
    EXPECT_TRUE(identical_bytes(one, split_image)) << name << ": split tiles give other floats";
  }
}

TEST(SplitLoops, RenderRefusesATimeBudgetOnSeveralRanks) {
  const Scene scene = load_scene("cornell");
  const RayTracer tracer(scene);
  ShuffledSplit split(2);
  const ScopedWorkSplit installed(&split);
  RenderOptions o;
  o.width = o.height = 16;
  o.spp = 4;
  o.time_budget_s = 1.0;
  o.progress = false;
  const Camera camera = Camera::framing(scene.bounds());
  try {
    Integrator::create("path", Params(nlohmann::json::object(), "--param"))
        ->render(tracer, camera, o);
    FAIL() << "a time budget was accepted on 2 ranks";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("--time"), std::string::npos) << e.what();
  }
  EXPECT_EQ(split.runs, 0);
}

using test::ChartedCornell;

TEST(SplitLoops, LightmapTexelsAndTheDenoiserGiveTheSameFloatsAsOneProcess) {
  const ChartedCornell cornell;
  for (const bake::LightmapBasis basis :
       {bake::LightmapBasis::kPlain, bake::LightmapBasis::kShL1}) {
    bake::LightmapBakeOptions o;
    o.basis = basis;
    o.spp = 12;  // 4 variance batches of 3
    o.seed = 5;
    o.denoise = true;
    o.progress = false;
    const bake::LightmapBake one =
        bake::bake_lightmap(cornell.scene, *cornell.tracer, cornell.raster, o);
    ShuffledSplit split(3);
    const ScopedWorkSplit installed(&split);
    const bake::LightmapBake split_bake =
        bake::bake_lightmap(cornell.scene, *cornell.tracer, cornell.raster, o);
    EXPECT_EQ(split.runs, 1);
    EXPECT_EQ(split_bake.rays, one.rays);
    EXPECT_TRUE(identical_bytes(one.variance, split_bake.variance)) << bake::to_string(basis);
    ASSERT_EQ(one.layers.size(), split_bake.layers.size());
    for (size_t i = 0; i < one.layers.size(); ++i)
      EXPECT_TRUE(identical_bytes(one.layers[i], split_bake.layers[i]))
          << bake::to_string(basis) << " layer " << i;
  }
}

TEST(SplitLoops, ExtraMapsGiveTheSameFloatsAsOneProcess) {
  const ChartedCornell cornell;
  bake::LightmapExtrasOptions o;
  o.ao = o.obscurance = o.bent_normal = true;
  o.rays = 24;
  o.seed = 3;
  o.progress = false;
  const bake::LightmapExtras one =
      bake::bake_lightmap_extras(cornell.scene, *cornell.tracer, cornell.raster, o);
  ShuffledSplit split(2);
  const ScopedWorkSplit installed(&split);
  const bake::LightmapExtras split_maps =
      bake::bake_lightmap_extras(cornell.scene, *cornell.tracer, cornell.raster, o);
  EXPECT_EQ(split.runs, 1);
  EXPECT_EQ(split_maps.rays, one.rays);
  EXPECT_TRUE(identical_bytes(one.ao, split_maps.ao));
  EXPECT_TRUE(identical_bytes(one.obscurance, split_maps.obscurance));
  EXPECT_TRUE(identical_bytes(one.obscurance_color, split_maps.obscurance_color));
  EXPECT_TRUE(identical_bytes(one.bent_normal, split_maps.bent_normal));
}

}  // namespace
}  // namespace illum

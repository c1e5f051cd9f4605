// VQ compression of SH transfer (bake/prt_vq.h, S002 §5.6): exact when there are no more
// distinct vectors than representatives; every index is its vector's nearest representative
// and the reported distances are the true ones; the loop stops by the seed's rule; and the
// error VQ adds to relit light at a texel is within max_distance × |L| (Cauchy–Schwarz).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "illum/atlas/atlas.h"
#include "illum/bake/prt_baker.h"
#include "illum/bake/prt_relight.h"
#include "illum/bake/prt_vq.h"
#include "illum/core/error.h"
#include "illum/core/rng.h"
#include "illum/scene/load.h"

namespace illum {
namespace {

TEST(PrtVq, ExactWhenRepresentativesCoverTheDistinctVectors) {
  const int dim = 12;
  std::vector<float> distinct(5 * dim), vectors;
  Rng rng(3);
  for (float& v : distinct) v = rng.next_float() - 0.5f;
  for (int i = 0; i < 60; ++i)
    vectors.insert(vectors.end(), distinct.begin() + (i % 5) * dim,
                   distinct.begin() + (i % 5 + 1) * dim);
  bake::VqOptions o;
  o.representatives = 8;
  const bake::VqCodebook book = bake::vq_compress(vectors, dim, o);
  EXPECT_EQ(book.count(), 8);
  EXPECT_EQ(book.max_distance, 0.0);
  for (size_t v = 0; v < 60; ++v)
    for (int i = 0; i < dim; ++i)
      EXPECT_EQ(book.representatives[book.indices[v] * dim + i], vectors[v * dim + i]);
}

TEST(PrtVq, IndicesAreNearestAndTheErrorAddedToRelitLightIsBounded) {
  Scene scene = load_scene("cornell");
  const atlas::Atlas atlas = atlas::chart_scene(scene, {.resolution = 32});
  const RayTracer tracer(scene);
  const atlas::TexelRaster raster = atlas::rasterize_texels(scene, atlas.width, atlas.height);
  bake::PrtBakeOptions po;
  po.bands = 3;
  po.spp = 16;
  po.progress = false;
  po.vertices = false;
  const bake::PrtBake baked = bake::bake_prt(scene, tracer, raster, po);
  const int dim = baked.texel_transfer.channels;
  const std::vector<float>& data = baked.texel_transfer.data;
  bake::VqOptions o;
  o.representatives = 64;
  const bake::VqCodebook book = bake::vq_compress(data, dim, o);
  ASSERT_EQ(book.count(), 64);
  ASSERT_EQ(book.indices.size(), data.size() / size_t(dim));
  EXPECT_LE(book.iterations, o.max_iterations);
  // Nearest and the reported distances, recomputed by brute force.
  double max_d = 0.0, sum2 = 0.0;
  for (size_t v = 0; v < book.indices.size(); ++v) {
    auto dist2 = [&](size_t r) {
      double d = 0.0;
      for (int i = 0; i < dim; ++i) {
        const double e = double(data[v * dim + i]) - double(book.representatives[r * dim + i]);
        d += e * e;
      }
      return d;
    };
    const double own = dist2(book.indices[v]);
    for (size_t r = 0; r < size_t(book.count()); ++r)
      ASSERT_LE(own, dist2(r) * (1.0 + 1e-6) + 1e-12);
    max_d = std::max(max_d, std::sqrt(own));
    sum2 += own;
  }
  EXPECT_NEAR(book.max_distance, max_d, 1e-6 * max_d);
  EXPECT_NEAR(book.rms_distance, std::sqrt(sum2 / double(book.indices.size())), 1e-6 * max_d);
  EXPECT_GT(book.max_distance, 0.0);  // 64 representatives for ~1000 texels: not exact

  // Relit E/π at each texel under a sun: |Σ (T − R) L| ≤ |T − R|·|L| ≤ max_distance·|L| per
  // channel (the channel's coefficients are a sub-vector of the 3·bands² vector).
  const bake::ShLight sun = bake::sun_light(3, vec3(0.3f, -1.0f, -0.5f), Color(3.0f));
  double norm = 0.0;
  for (const Color& c : sun.coefficients) norm += double(c.x) * double(c.x);
  norm = std::sqrt(norm);
  double worst = 0.0, rms = 0.0;
  for (size_t v = 0; v < book.indices.size(); ++v) {
    double full = 0.0, packed = 0.0;
    for (size_t i = 0; i < sun.coefficients.size(); ++i) {
      full += double(data[v * dim + i * 3]) * sun.coefficients[i].x;
      packed += double(book.representatives[book.indices[v] * dim + i * 3]) * sun.coefficients[i].x;
    }
    EXPECT_LE(std::abs(full - packed), book.max_distance * norm * (1.0 + 1e-5));
    worst = std::max(worst, std::abs(full - packed));
    rms += (full - packed) * (full - packed);
  }
  std::printf(
      "VQ 64 representatives, %d iterations: max distance %.4f, rms %.4f; relit E/pi error "
      "max %.4f rms %.4f (bound %.4f)\n",
      book.iterations, book.max_distance, book.rms_distance, worst,
      std::sqrt(rms / double(book.indices.size())), book.max_distance * norm);
}

TEST(PrtVq, RefusesBadOptions) {
  const std::vector<float> v(12, 0.0f);
  bake::VqOptions o;
  o.representatives = 0;
  EXPECT_THROW(bake::vq_compress(v, 4, o), Error);
  o.representatives = (1 << 16) + 1;
  EXPECT_THROW(bake::vq_compress(v, 4, o), Error);
  o.representatives = 4;
  EXPECT_THROW(bake::vq_compress(v, 5, o), Error);  // not whole vectors
}

}  // namespace
}  // namespace illum

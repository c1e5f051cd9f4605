// `illum-bench photons`: photon-map build and query times, illum's left-balanced implicit
// kd-tree (render/photon_map.h) against nanoflann (Debian libnanoflann-dev, leaf size 10)
// on the same points. Photons are random, not traced: uniform on the six faces of the unit
// cube (photons lie on surfaces, so the density is two-dimensional as in a real map);
// queries are random points on the same faces. k-NN queries take the k nearest (no radius
// bound); radius queries use the radius that holds k photons on average, r = √(k·A/(πN)).
// Queries run in parallel over all threads (as in rendering); rounds interleave the two
// structures and the medians are reported.
// GCC 12 reports a false -Wnull-dereference inside std::vector construction instantiated by
// nanoflann's index; the file only benchmarks, so the warning is silenced here.
#pragma GCC diagnostic ignored "-Wnull-dereference"
#include <nanoflann.hpp>

#include <chrono>
#include <cstdio>
#include <vector>

#include "illum/core/error.h"
#include "illum/core/parallel.h"
#include "illum/core/rng.h"
#include "illum/render/photon_map.h"
#include "suites.h"

namespace illum::bench {
namespace {

struct Cloud {
  const std::vector<vec3>* points;
  size_t kdtree_get_point_count() const { return points->size(); }
  float kdtree_get_pt(size_t i, size_t d) const { return (*points)[i][static_cast<int>(d)]; }
  template <class B>
  bool kdtree_get_bbox(B&) const {
    return false;
  }
};
using NanoTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Cloud>,
                                                     Cloud, 3, uint32_t>;

std::vector<vec3> cube_surface_points(size_t n, uint64_t seed) {
  std::vector<vec3> p(n);
  parallel_for(static_cast<int64_t>(n), [&](int64_t b, int64_t e) {
    for (int64_t i = b; i < e; ++i) {
      Rng rng(seed, static_cast<uint64_t>(i));
      const uint32_t face = rng.next_bounded(6);
      const float u = rng.next_float(), v = rng.next_float();
      const float w = (face & 1) ? 1.0f : 0.0f;
      const int axis = static_cast<int>(face / 2);
      vec3 q;
      q[axis] = w;
      q[(axis + 1) % 3] = u;
      q[(axis + 2) % 3] = v;
      p[static_cast<size_t>(i)] = q;
    }
  });
  return p;
}

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

int run_photons(SuiteArgs args) {
  CLI::App app("photon-map build and query times: illum's kd-tree vs nanoflann",
               "illum-bench photons");
  std::vector<int64_t> counts{1000000, 10000000};
  int queries = 200000, k = 50, rounds = 3;
  std::string json_path;
  app.add_option("--counts", counts, "photon counts")->capture_default_str();
  app.add_option("--queries", queries, "queries per round")
      ->capture_default_str()
      ->check(CLI::Range(1, 1 << 26));
  app.add_option("--k", k, "neighbours per query")
      ->capture_default_str()
      ->check(CLI::Range(1, 10000));
  app.add_option("--rounds", rounds, "timed rounds (median reported)")
      ->capture_default_str()
      ->check(CLI::Range(1, 100));
  app.add_option("--json", json_path, "write the results to this JSON file");
  if (!parse_args(app, args)) return 0;
  for (int64_t c : counts)
    if (c < 1 || c > 200000000)
      throw Error(fmt::format("photons: --counts {} is out of range [1, 2e8]", c));

  nlohmann::json out = {{"suite", "photons"},
                        {"machine", machine_info()},
                        {"points", "random, uniform on the faces of the unit cube"},
                        {"k", k},
                        {"queries", queries},
                        {"results", nlohmann::json::array()}};
  std::printf("%10s %9s %9s | %12s %12s | %12s %12s | %12s %12s\n", "photons", "build", "nano",
              "knn us/q", "nano", "radius us/q", "nano", "knn ratio", "radius ratio");
  for (int64_t count : counts) {
    const std::vector<vec3> points = cube_surface_points(static_cast<size_t>(count), 1);
    const std::vector<vec3> qs = cube_surface_points(static_cast<size_t>(queries), 2);
    const float radius =
        std::sqrt(static_cast<float>(k) * 6.0f / (kPi * static_cast<float>(count)));
    std::vector<double> build_ours, build_nano, knn_ours, knn_nano, rad_ours, rad_nano;
    double checksum_ours = 0.0, checksum_nano = 0.0;
    for (int round = 0; round < rounds; ++round) {
      std::vector<Photon> photons(points.size());
      for (size_t i = 0; i < points.size(); ++i) photons[i].position = points[i];
      double t0 = now();
      const PhotonMap map(std::move(photons));
      build_ours.push_back(now() - t0);
      const Cloud cloud{&points};
      t0 = now();
      NanoTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
      build_nano.push_back(now() - t0);

      std::vector<double> sums(static_cast<size_t>(queries));
      t0 = now();
      parallel_for(
          queries,
          [&](int64_t b, int64_t e) {
            std::vector<PhotonNeighbor> nb;
            for (int64_t i = b; i < e; ++i)
              sums[static_cast<size_t>(i)] = map.knn(qs[static_cast<size_t>(i)], k, kInf, &nb);
          },
          256);
      knn_ours.push_back((now() - t0) / queries * 1e6);
      checksum_ours = 0.0;
      for (double s : sums) checksum_ours += s;
      t0 = now();
      parallel_for(
          queries,
          [&](int64_t b, int64_t e) {
            std::vector<uint32_t> idx(static_cast<size_t>(k));
            std::vector<float> d2(static_cast<size_t>(k));
            for (int64_t i = b; i < e; ++i) {
              nanoflann::KNNResultSet<float, uint32_t> rs(static_cast<uint32_t>(k));
              rs.init(idx.data(), d2.data());
              tree.findNeighbors(rs, &qs[static_cast<size_t>(i)].x, nanoflann::SearchParams());
              sums[static_cast<size_t>(i)] = rs.size() ? d2[rs.size() - 1] : 0.0f;
            }
          },
          256);
      knn_nano.push_back((now() - t0) / queries * 1e6);
      checksum_nano = 0.0;
      for (double s : sums) checksum_nano += s;

      t0 = now();
      parallel_for(
          queries,
          [&](int64_t b, int64_t e) {
            for (int64_t i = b; i < e; ++i) {
              size_t c = 0;
              map.for_each_in_radius(qs[static_cast<size_t>(i)], radius,
                                     [&](uint32_t, float) { ++c; });
              sums[static_cast<size_t>(i)] = static_cast<double>(c);
            }
          },
          256);
      rad_ours.push_back((now() - t0) / queries * 1e6);
      t0 = now();
      parallel_for(
          queries,
          [&](int64_t b, int64_t e) {
            std::vector<std::pair<uint32_t, float>> found;
            for (int64_t i = b; i < e; ++i)
              sums[static_cast<size_t>(i)] = static_cast<double>(
                  tree.radiusSearch(&qs[static_cast<size_t>(i)].x, radius * radius, found,
                                    nanoflann::SearchParams(32, 0.0f, false)));
          },
          256);
      rad_nano.push_back((now() - t0) / queries * 1e6);
    }
    // The two k-NN searches must agree on the k-th distance (same points, same queries).
    if (std::abs(checksum_ours - checksum_nano) > 1e-4 * std::abs(checksum_nano))
      throw Error(
          fmt::format("photons: k-NN results differ ({} vs {})", checksum_ours, checksum_nano));
    const double bo = median(build_ours), bn = median(build_nano), ko = median(knn_ours),
                 kn = median(knn_nano), ro = median(rad_ours), rn = median(rad_nano);
    std::printf("%10lld %8.3fs %8.3fs | %12.3f %12.3f | %12.3f %12.3f | %12.2f %12.2f\n",
                static_cast<long long>(count), bo, bn, ko, kn, ro, rn, kn / ko, rn / ro);
    out["results"].push_back({{"photons", count},
                              {"build_s", {{"illum", bo}, {"nanoflann", bn}}},
                              {"knn_us_per_query", {{"illum", ko}, {"nanoflann", kn}}},
                              {"radius_us_per_query", {{"illum", ro}, {"nanoflann", rn}}},
                              {"radius", radius}});
  }
  if (!json_path.empty()) write_json(json_path, out);
  return 0;
}

}  // namespace illum::bench

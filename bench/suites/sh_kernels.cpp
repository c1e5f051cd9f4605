// Google Benchmark kernels for core/sh.h and core/sh_rotation.h: evaluation of every band
// up to n (fast path and recurrence, float and double), building a rotation and applying
// it, so the cost of higher band counts shows up in one run.
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "illum/core/rng.h"
#include "illum/core/sampling.h"
#include "illum/core/sh.h"
#include "illum/core/sh_rotation.h"

namespace illum {
namespace {

constexpr size_t kDirections = 1024;

std::vector<glm::dvec3> directions() {
  Rng rng(5);
  std::vector<glm::dvec3> d(kDirections);
  for (auto& w : d) w = glm::dvec3(sample_uniform_sphere(vec2(rng.next_float(), rng.next_float())));
  return d;
}

template <class T, bool kRecurrence>
void BM_ShEvaluate(benchmark::State& state) {
  const int bands = static_cast<int>(state.range(0));
  const std::vector<glm::dvec3> dirs = directions();
  std::vector<glm::vec<3, T>> w(dirs.begin(), dirs.end());
  std::vector<T> y(bands * bands);
  size_t i = 0;
  for (auto _ : state) {
    if constexpr (kRecurrence)
      sh::evaluate_recurrence<T>(bands, w[i++ % kDirections], y);
    else
      sh::evaluate<T>(bands, w[i++ % kDirections], y);
    benchmark::DoNotOptimize(y.data());
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ShEvaluate<float, false>)->Arg(2)->Arg(3);
BENCHMARK(BM_ShEvaluate<float, true>)->Arg(2)->Arg(3)->Arg(4)->Arg(9)->Arg(17);
BENCHMARK(BM_ShEvaluate<double, true>)->Arg(3)->Arg(9)->Arg(17);

void BM_ShRotationBuild(benchmark::State& state) {
  const int bands = static_cast<int>(state.range(0));
  const glm::dmat3 r = glm::dmat3(glm::rotate(glm::dmat4(1.0), 0.7, glm::dvec3(1, 2, 3)));
  for (auto _ : state) {
    sh::ShRotation rotation(bands, r);
    benchmark::DoNotOptimize(&rotation);
  }
}
BENCHMARK(BM_ShRotationBuild)->Arg(3)->Arg(9)->Arg(17);

void BM_ShRotationApply(benchmark::State& state) {
  const int bands = static_cast<int>(state.range(0));
  const glm::dmat3 r = glm::dmat3(glm::rotate(glm::dmat4(1.0), 0.7, glm::dvec3(1, 2, 3)));
  const sh::ShRotation rotation(bands, r);
  std::vector<glm::vec3> in(bands * bands, glm::vec3(0.5f)), out(bands * bands);
  for (auto _ : state) {
    rotation.apply<glm::vec3>(in, out);
    benchmark::DoNotOptimize(out.data());
  }
}
BENCHMARK(BM_ShRotationApply)->Arg(3)->Arg(9)->Arg(17);

}  // namespace
}  // namespace illum

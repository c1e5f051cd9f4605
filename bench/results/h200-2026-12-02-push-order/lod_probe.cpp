// How far meshoptimizer simplifies Sibenik's welded triangles (a level of detail for the shadow
// casters, not built). One-off probe, CPU only; output in README.md:
//   g++ -O2 -std=c++17 lod_probe.cpp -lmeshoptimizer -o /tmp/lod_probe && /tmp/lod_probe
//   ../shared/scenes/sibenik/sibenik.obj
#include <meshoptimizer.h>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>
int main(int argc, char** argv) {
  std::ifstream in(argv[1]);
  std::vector<float> v;
  std::vector<unsigned> idx;
  std::string line;
  while (std::getline(in, line)) {
    if (line.size() > 2 && line[0] == 'v' && line[1] == ' ') {
      std::istringstream s(line.substr(2));
      float x, y, z;
      s >> x >> y >> z;
      v.insert(v.end(), {x, y, z});
    } else if (line.size() > 2 && line[0] == 'f' && line[1] == ' ') {
      std::istringstream s(line.substr(2));
      std::string t;
      std::vector<unsigned> f;
      while (s >> t) {
        long k = std::atol(t.c_str());
        f.push_back(k > 0 ? unsigned(k - 1) : unsigned(v.size() / 3 + k));
      }
      for (size_t i = 1; i + 1 < f.size(); ++i) idx.insert(idx.end(), {f[0], f[i], f[i + 1]});
    }
  }
  size_t nv = v.size() / 3;
  std::vector<unsigned> w(idx.size());
  meshopt_generateShadowIndexBuffer(w.data(), idx.data(), idx.size(), v.data(), nv, 12, 12);
  float scale = meshopt_simplifyScale(v.data(), nv, 12);
  std::printf("triangles %zu vertices %zu scale %.2f\n", idx.size() / 3, nv, scale);
  for (float e : {0.02f, 0.05f, 0.1f, 0.2f}) {
    std::vector<unsigned> o2(w.size());
    float e2 = 0;
    size_t n2 =
        meshopt_simplifySloppy(o2.data(), w.data(), w.size(), v.data(), nv, 12, 0, e / scale, &e2);
    std::printf("error %.2f m sloppy: %zu triangles (%.1f%%), result error %.3f m\n", e, n2 / 3,
                100.0 * n2 / w.size(), e2 * scale);
  }
  for (float e : {0.01f, 0.02f, 0.05f, 0.1f, 0.2f}) {
    for (unsigned opt : {0u, unsigned(meshopt_SimplifyLockBorder)}) {
      std::vector<unsigned> out(w.size());
      float err = 0;
      size_t n = meshopt_simplify(out.data(), w.data(), w.size(), v.data(), nv, 12, 0, e / scale,
                                  opt, &err);
      std::printf("error %.2f m %s: %zu triangles (%.1f%%), result error %.3f m\n", e,
                  opt ? "lock border" : "free border", n / 3, 100.0 * n / w.size(), err * scale);
    }
  }
}

// Ratio of the mean of two renders to a reference, overall and the furthest 16x16 region
// (bench/results/dev2core-2026-12-02-speed/README.md says how it is built and run).
#include <cmath>
#include <cstdio>
#include "illum/core/image.h"
using namespace illum;
int main(int argc, char** argv) {
  Image a = read_image(argv[1], false), b = read_image(argv[2], false),
        r = read_image(argv[3], false);
  int w = r.width(), h = r.height(), R = 16;
  double sa = 0, sr = 0, worst = 1;
  int wx = 0, wy = 0;
  for (int by = 0; by < h; by += R)
    for (int bx = 0; bx < w; bx += R) {
      double ra = 0, rr = 0;
      for (int y = by; y < std::min(h, by + R); ++y)
        for (int x = bx; x < std::min(w, bx + R); ++x) {
          Color ca = (a.rgb(x, y) + b.rgb(x, y)) * 0.5f, cr = r.rgb(x, y);
          ra += ca.r + ca.g + ca.b;
          rr += cr.r + cr.g + cr.b;
        }
      sa += ra;
      sr += rr;
      if (rr > 0 && std::abs(ra / rr - 1) > std::abs(worst - 1)) {
        worst = ra / rr;
        wx = bx;
        wy = by;
      }
    }
  std::printf("mean new/ref %.4f, furthest 16x16 region (%d,%d): %.4f\n", sa / sr, wx, wy, worst);
}

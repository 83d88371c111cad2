// The randomised stability check at a chosen size:
//   tetdsr-stress [seeds=1000] [pixels per side per camera=64]
// Each seed: a jittered lattice, a random quadric, 4 random cameras (perspective and parallel).
// Prints the totals against the targets; exits non-zero if a target is missed.
#include "StabilityCases.h"

#include <cstdio>
#include <cstdlib>

int main(int argc, char* argv[])
{
  const unsigned seeds = argc > 1 ? static_cast<unsigned>(std::atoi(argv[1])) : 1000;
  const int pixels = argc > 2 ? std::atoi(argv[2]) : 64;
  long long rays = 0, excluded = 0, hits = 0, misses = 0, falseHits = 0;
  double depth = 0.0, normal = 0.0;
  for (unsigned seed = 1; seed <= seeds; ++seed)
  {
    const tetdsr_test::Case c = tetdsr_test::randomCase(seed, pixels);
    const tetdsr_test::Figures f = tetdsr_test::evaluateScene(c);
    rays += f.rays;
    excluded += f.excluded;
    hits += f.hits;
    misses += f.misses;
    falseHits += f.falseHits;
    depth = std::max(depth, f.maxDepthError);
    normal = std::max(normal, f.maxNormalError);
    if (f.misses || f.falseHits)
      std::printf("seed %u: %d misses, %d false hits\n", seed, f.misses, f.falseHits);
  }
  std::printf("%u seeds, %lld rays: %lld excluded (band), %lld hits, %lld misses, %lld false "
              "hits, max depth error %.2e of the diagonal, max normal error %.2e rad\n",
    seeds, rays, excluded, hits, misses, falseHits, depth, normal);
  const bool ok = misses == 0 && falseHits == 0 && depth <= 1e-9 && normal <= 1e-6;
  std::printf("%s\n", ok ? "targets met" : "TARGETS MISSED");
  return ok ? EXIT_SUCCESS : EXIT_FAILURE;
}

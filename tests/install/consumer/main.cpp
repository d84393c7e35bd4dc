// Uses an installed iaa as a library: an interval evaluation, a scene file loaded with an override
// (application layer), a small render and an enclosure. Prints one line per result; exits 1 on a
// wrong answer. Usage: consumer SCENE.toml
#include <iaa/app/scene_loading.h>
#include <iaa/core/error.h>
#include <iaa/enclose/octree.h>
#include <iaa/expr/eval_interval.h>
#include <iaa/render/render.h>

#include <cstdio>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: consumer SCENE.toml\n");
    return 2;
  }
  try {
    // The unit sphere's f over a box that misses it: certified empty.
    const iaa::Tape tape = iaa::Tape::parse("x^2 + y^2 + z^2 - 1");
    iaa::Interval f;
    {
      iaa::RoundingScope scope;
      iaa::IntervalEval eval(tape);
      f = eval.eval(iaa::Box3{{2, 2, 2}, {3, 3, 3}});
    }
    std::printf("F over [2,3]^3 = [%g, %g]\n", f.lo(), f.hi());
    const iaa::Scene scene = iaa::app::load_scene(argv[1], {"image.width=48", "image.height=32"});
    const iaa::Film film = iaa::render(scene, scene.settings);
    std::printf("render %dx%d: %llu covered, %llu uncertain\n", film.width, film.height,
                (unsigned long long)film.stats.covered, (unsigned long long)film.stats.uncertain);
    iaa::EncloseSettings es;
    es.bounds = scene.bounds;
    es.depth = 4;
    const iaa::Enclosure enc = iaa::enclose(*scene.tape, es);
    std::printf("enclosure: %zu boxes\n", enc.cells.size());
    const bool ok = f.lo() > 0 && film.stats.covered > 0 && !enc.cells.empty();
    return ok ? 0 : 1;
  } catch (const iaa::Error& e) {
    std::fprintf(stderr, "consumer: %s\n", e.what());
    return 1;
  }
}

// The render flags shared by render, inspect and bench render (see render_flags.h).
#include "iaa/render_flags.h"

namespace iaa::cli {

void add_render_flags(CLI::App& app, RenderFlags* f, unsigned parts) {
  if (parts & kMethodFlag) {
    app.add_option("--method", f->method, "iaa (default), point, 'grid N' (or gridN), adaptive");
  }
  app.add_option("--max-level", f->max_level,
                 "subdivision levels below the pixel (0..6, default 2)");
  app.add_option("--threshold", f->threshold, "iaa: estimator threshold (0..2)");
  app.add_option("--depth-tol", f->depth_tol, "iaa: depth tolerance relative to the beam width");
  app.add_option("--adaptive-threshold", f->adaptive_threshold,
                 "adaptive: colour threshold (0..1)");
  if (parts & kImageSizeFlags) {
    app.add_option("--width", f->width, "image width in pixels (overrides the scene)");
    app.add_option("--height", f->height, "image height in pixels (overrides the scene)");
  }
  if (parts & kWindowFlag) {
    app.add_option("--window", f->window, "render only pixels X0,Y0,X1,Y1 (X1, Y1 exclusive)");
  }
  app.add_flag("--no-shadows", f->no_shadows, "do not cast shadow rays");
  app.add_flag("--shadows", f->shadows, "cast shadow rays");
}

}  // namespace iaa::cli

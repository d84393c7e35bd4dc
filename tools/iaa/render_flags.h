// The render flags that `iaa render`, `iaa inspect` and `iaa bench render` share: the options that
// map to RenderSettings (method, subdivision levels, thresholds, depth tolerance, shadows, pixel
// window) and the image size. What they mean and how they override a scene is the application
// layer's (app/render_flags.h, shared with the Python module); this adds them to a command line.
#pragma once

#include <CLI/CLI.hpp>

#include "app/render_flags.h"

namespace iaa::cli {

using app::RenderFlags;

/// Flags a command may leave out of the group; the levels, thresholds and shadows are always in.
/// `iaa bench render` chooses the methods and the image size itself and renders whole images.
enum RenderFlagParts : unsigned {
  kMethodFlag = 1u << 0,      ///< --method
  kImageSizeFlags = 1u << 1,  ///< --width, --height
  kWindowFlag = 1u << 2,      ///< --window
};

/// Adds the render flags (those of `parts` and the ones always in) to a command or subcommand.
void add_render_flags(CLI::App& app, RenderFlags* flags, unsigned parts);

}  // namespace iaa::cli

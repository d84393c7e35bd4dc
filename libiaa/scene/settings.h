// What the renderer computes: the method, its levels, thresholds and tolerances, an optional
// window of pixels, and shadows. How it runs (threads, progress) is Exec (core/exec.h): the two
// are kept apart so that results never depend on how they were computed.
#pragma once

#include <string>
#include <string_view>

namespace iaa {

/// The rendering methods (docs/design.md, "Rendering").
enum class RenderMethod {
  kIaa,       ///< interval adaptive antialiasing: beams, certified per pixel
  kPoint,     ///< one ray through each pixel centre
  kGrid,      ///< grid_n x grid_n regular rays per pixel, averaged
  kAdaptive,  ///< Whitted's adaptive supersampling with corner rays
};

/// Name of a method as written in scenes and on the command line ("iaa", "point", "grid",
/// "adaptive").
std::string_view method_name(RenderMethod m);
/// Parses a method name; "grid16" and "grid 16" also set `grid_n`. Throws SettingError.
RenderMethod parse_method(std::string_view text, int* grid_n);

/// A rectangle of whole pixels [x0, x1) x [y0, y1] of the image (pbrt's --pixelbounds).
struct PixelWindow {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< x1, y1 exclusive
  bool empty() const { return x1 <= x0 || y1 <= y0; }
  bool contains(int x, int y) const { return x0 <= x && x < x1 && y0 <= y && y < y1; }
};

/// Settings of one render. Defaults were chosen by measurement (docs/render.md).
struct RenderSettings {
  RenderMethod method = RenderMethod::kIaa;
  /// Rays per pixel side for kGrid (1..64).
  int grid_n = 16;
  /// Subdivision depth below the pixel for kIaa and kAdaptive (0..6); leaves of 1/4^max_level
  /// pixel area.
  int max_level = 2;
  /// kIaa: a Full beam is shaded once when the width of its estimator interval (the interval
  /// dot product of the unit normal over the hit box with the unit beam direction) is at most
  /// this (0..2; 0 always splits down to max_level).
  double estimator_threshold = 1.5;
  /// kIaa: a depth piece of a beam stops being bisected when its depth extent is at most
  /// depth_tolerance times the beam's lateral width at that depth (relative;
  /// kMinDepthTolerance..kMaxDepthTolerance). Soundness never depends on it (a Miss is only
  /// claimed when every piece excludes 0); the time does, about as 1 / depth_tolerance below 1.
  double depth_tolerance = 1.0;
  /// kAdaptive: a square is split while two corner colours differ by more than this in some
  /// channel (0..1).
  double adaptive_threshold = 0.1;
  /// Cast shadow rays to every light (tested with the guaranteed 1D search).
  bool shadows = false;
  /// Render only these pixels (the others stay background with zero counts); empty = all.
  PixelWindow window;

  static constexpr int kMaxLevel = 6;
  /// A piece thinner than the beam is no tighter a box, but every such piece near the surface is
  /// searched: the teardrop at 64x64 took 0.05 s at 1, 0.32 s at 1e-3, 25 s at 1e-5 and 236 s at
  /// 1e-6 (found by fuzz_scene: 16x16 pixels ran for minutes). 1e-3 keeps a render within
  /// about 10x the default's time.
  static constexpr double kMinDepthTolerance = 1e-3;
  static constexpr double kMaxDepthTolerance = 1e3;
  static constexpr int kMaxGrid = 64;

  /// Throws SettingError naming the setting and its limits.
  void validate() const;
  /// Throws SettingError when the window does not lie inside a width x height image.
  void validate_window(int width, int height) const;
};

}  // namespace iaa

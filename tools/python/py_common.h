// The pieces every binding of the Python module `iaa` shares: the scene as Python holds it, NumPy
// arrays over C++ results without copies, JSON reports as dicts, and running the library's work
// off the Python thread so that the GIL is free, progress reaches a Python callback and Ctrl-C
// cancels through the library's own cancel (core/exec.h).
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <nlohmann/json.hpp>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/exec.h"
#include "scene/scene.h"

namespace iaa::py {

namespace pb = pybind11;

/// A scene as Python holds it: the parsed Scene and where it came from (the TOML text, its name in
/// messages and the overrides applied), so that more overrides (render's width and height,
/// Scene.with_overrides) are applied to the text and checked exactly like keys of the file.
struct PyScene {
  std::string text;    ///< the TOML text ("" for a scene built in Python from overrides)
  std::string source;  ///< the file's path, or "iaa.Scene"
  std::vector<std::string> overrides;  ///< "key=value", in order
  Scene scene;
};

/// Parses text + overrides into a PyScene; throws iaa::Error as the scene loader does.
PyScene parse_py_scene(std::string text, std::string source, std::vector<std::string> overrides);

/// A capsule that owns `p` (deleted when the last array based on it is gone).
template <class Owner>
pb::capsule owner_capsule(std::shared_ptr<Owner> p) {
  auto* held = new std::shared_ptr<Owner>(std::move(p));
  return pb::capsule(held, [](void* q) { delete static_cast<std::shared_ptr<Owner>*>(q); });
}

/// A C-contiguous array of `shape` over `data`, which `base` keeps alive: no copy.
template <class T>
pb::array_t<T> array_over(const T* data, std::vector<pb::ssize_t> shape, const pb::handle& base) {
  return pb::array_t<T>(std::move(shape), data, base);
}

/// A JSON value as Python objects (dict, list, str, int, float, bool, None).
pb::object to_python(const nlohmann::json& j);

/// Runs work(exec) on a worker thread, with `threads` workers (0 = all cores; SettingError outside
/// 0..1024), while the calling thread waits with the GIL released. About every 50 ms the calling
/// thread checks for signals (Ctrl-C raises KeyboardInterrupt there) and calls `progress` (unless
/// None) as progress(phase: str, done: int, total: int); once more at the end. If either raises,
/// the work is cancelled through exec's Progress, waited for, and the Python exception propagates;
/// otherwise an exception of the work propagates (iaa::Error becomes ValueError).
void run_cancellable(const std::function<void(const Exec&)>& work, int threads,
                     const pb::object& progress);

void bind_scene(pb::module_& m);
void bind_eval(pb::module_& m);
void bind_render(pb::module_& m);
void bind_enclose(pb::module_& m);
void bind_mesh(pb::module_& m);

}  // namespace iaa::py

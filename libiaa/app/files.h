// Application layer: used by tools/ and viz/, never by the library modules.
// File input and output for the tools and the viewer: whole-file reads with clear errors, and
// atomic writes (write to a temporary file beside the target, then rename) so that a failed or
// interrupted command never leaves a half-written output behind.
#pragma once

#include <functional>
#include <string>

namespace iaa::app {

/// Reads a whole file; throws iaa::Error naming the path when it cannot.
std::string read_file(const std::string& path);

/// Throws iaa::Error when `path` cannot be created because its directory does not exist or is
/// not writable, so that a command can fail before its work rather than after it. The message is
/// `prefix` (e.g. the option's name, "--vtk: ") then "cannot write 'PATH': directory 'DIR' ...".
void check_writable(const std::string& path, const std::string& prefix = "");

/// Calls write(tmp_path) to produce the file, then renames tmp_path to `path`. On any exception
/// the temporary file is removed and the exception propagates. Fails early, with a message naming
/// the path, when the target directory does not exist or is not writable.
void write_atomically(const std::string& path,
                      const std::function<void(const std::string&)>& write);

/// Writes `contents` to `path` atomically.
void write_text_atomically(const std::string& path, const std::string& contents);

/// Lower-case extension of a path without the dot ("png" for "a/b.PNG"), empty if none.
std::string extension_of(const std::string& path);

}  // namespace iaa::app

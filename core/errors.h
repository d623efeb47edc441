// Exceptions for bad input. They are thrown deep in the libraries and caught at the command
// line, which prints them and exits with status 2 (CONTRIBUTING.md, "Errors and exit codes").
// Tests can assert them; nothing in a library calls exit().
#pragma once

#include <stdexcept>
#include <string>

namespace penumbra {

// Base of every error caused by the user's input rather than by a bug in penumbra.
class InputError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

// A scene file that cannot be read or breaks the glTF specification. The message starts with the
// file name and names the place in it as a JSON pointer, e.g.
// "box.gltf: /meshes/3/primitives/0/indices: index 812 past the vertex count 800".
class SceneError : public InputError {
  public:
    SceneError(const std::string& file, const std::string& pointer, const std::string& what)
        : InputError(file + (pointer.empty() ? "" : ": " + pointer) + ": " + what) {}
};

// A pass script (TOML) error, "script.toml:42:17: pass.epsilon: expected ...".
class ScriptError : public InputError {
  public:
    ScriptError(const std::string& file, int line, int column, const std::string& what)
        : InputError(file + ":" + std::to_string(line) + ":" + std::to_string(column) + ": " +
                     what) {}
};

// Bad command-line usage or option values.
class UsageError : public InputError {
  public:
    using InputError::InputError;
};

}  // namespace penumbra

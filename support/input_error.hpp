// The one error type for bad input: it names the file and the place (line, byte offset, accessor, frame).
//
// The readers (sim_io) and the engines (mesh_validation.hpp) never print and never abort: they throw
// InputError at the boundary where input enters, and the CLI turns it into one line on stderr and a non-zero
// exit.
#pragma once

#include <stdexcept>
#include <string>

namespace pleat {

class InputError : public std::runtime_error {
 public:
  /// `place` is human-readable, e.g. "line 12", "byte 4096", "accessor 3", "frame 17"; may be empty.
  InputError(std::string file, std::string place, const std::string& what)
      : std::runtime_error(format(file, place, what)),
        m_file(std::move(file)),
        m_place(std::move(place)),
        m_reason(what) {}

  const std::string& file() const { return m_file; }
  const std::string& place() const { return m_place; }
  /// What is wrong, without the file and the place.
  const std::string& reason() const { return m_reason; }

 private:
  static std::string format(const std::string& file, const std::string& place, const std::string& what) {
    std::string s = file;
    if (!place.empty()) s += ":" + place;
    return s + ": " + what;
  }
  std::string m_file;
  std::string m_place;
  std::string m_reason;
};

/// Bad arguments handed to a library entry (mesh_validation.hpp: a frame of the wrong size, a non-finite
/// position, an index out of range); file() names the entry (e.g. "compute_visibility"). To a caller of the
/// library it is bad input like any other InputError. The command line hands the entries only sequences it
/// read and validated, so there it is a bug in pleat: exit status 1, not 2.
class ArgumentError : public InputError {
 public:
  using InputError::InputError;
};

}  // namespace pleat

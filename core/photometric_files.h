// Readers of measured luminaire photometry into a Photometry (core/photometry.h): IES LM-63 files
// (.ies; the 1986 format without a format line, IESNA91, IESNA:LM-63-1995, IESNA:LM-63-2002 and
// IES:LM-63-2019) and EULUMDAT files (.ldt, Stockmar 1990). A file that breaks its format throws
// a PhotometricFileError naming the file and the line.
#pragma once

#include "core/errors.h"
#include "core/photometry.h"

#include <filesystem>
#include <string>
#include <string_view>

namespace penumbra {

// A photometric file that breaks its format: "road.ldt:42: what is wrong". (A file that cannot be
// opened is an InputError "road.ldt: cannot be opened".)
class PhotometricFileError : public InputError {
  public:
    PhotometricFileError(const std::string& file, int line, const std::string& what)
        : InputError(file + ":" + std::to_string(line) + ": " + what) {}
};

// IES LM-63, photometric types C and B (type A and TILT=<file> are refused); the table is the
// file's candela values scaled as IesHeader says, unfolded by the symmetry its horizontal angles
// declare.
Photometry readIes(const std::filesystem::path& file);
// The same from a file's text; `name` names it in messages (an IES profile in a glTF buffer).
Photometry parseIes(std::string_view text, const std::string& name);

// EULUMDAT, every symmetry indicator; the table is in cd, as LdtHeader says.
Photometry readLdt(const std::filesystem::path& file);
Photometry parseLdt(std::string_view text, const std::string& name);

}  // namespace penumbra

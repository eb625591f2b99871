// ISO 5436-2 x3p files: a zip archive with main.xml (the grid, axes, data type) and the binary
// heights it links.  Built with libzip and libxml2 where both were found (GFMD_HAVE_X3P);
// otherwise the reader refuses every x3p file with a message saying how to build it in.
#ifndef GFMD_SRC_X3P_HPP
#define GFMD_SRC_X3P_HPP

#include <string>

#include "topography.hpp"

namespace gfmd {

// Whether this build reads x3p files (libzip and libxml2 were found).
bool x3p_supported();
// Whether the bytes are a zip archive (the x3p container; detection looks no further).
bool looks_like_zip(const std::string &bytes);
// The topography of an x3p file's bytes, lengths in the caller's unit (its length in metres;
// x3p's unit is the metre).  GFMD_ERR_FORMAT naming what is wrong and where; GFMD_ERR_STATE in a
// build without x3p support.
Topography from_x3p(const std::string &bytes, double unit);

}  // namespace gfmd

#endif

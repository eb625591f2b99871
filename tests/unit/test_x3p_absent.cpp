// The x3p reader of a build without libzip and libxml2 (src/x3p.cpp compiled without
// GFMD_HAVE_X3P, as GFMD_X3P=OFF or missing packages build it): every x3p file is refused with
// GFMD_ERR_STATE and a message naming the packages, and zip archives are still recognised (so
// GFMD_TOPO_AUTO reports that, not a text-matrix error).
#include <cstdio>
#include <cstring>
#include <string>

#include "error.hpp"
#include "gfmd.h"
#include "x3p.hpp"

int main() {
    const std::string zip("PK\x03\x04 an archive", 16);
    if (!gfmd::looks_like_zip(zip) || gfmd::looks_like_zip("# a text matrix")) {
        std::puts("FAILED: zip archives are not told from text");
        return 1;
    }
    try {
        (void)gfmd::from_x3p(zip, 1.0);
    } catch (const gfmd::Error &e) {
        if (e.status() == GFMD_ERR_STATE && std::strstr(e.what(), "libzip-dev libxml2-dev") != nullptr) {
            std::printf("refused as it must be: %s\n", e.what());
            return 0;
        }
        std::printf("FAILED: status %d, message '%s'\n", e.status(), e.what());
        return 1;
    }
    std::puts("FAILED: an x3p file was read without libzip");
    return 1;
}

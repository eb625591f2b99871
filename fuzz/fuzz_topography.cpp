// libFuzzer target for the topography readers: the first byte picks the format (GFMD_TOPO_AUTO
// and each format forced, modulo their count), the rest is the file.  Every read must end in
// GFMD_OK or a clear status (never a crash, a leak or an allocation beyond the file's length:
// -rss_limit_mb catches one); a topography read is then filled, detrended and transformed.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "gfmd.h"

namespace {

// the file each input is written to: one per process, removed at exit
struct Scratch {
    std::string path;
    Scratch() {
        char name[] = "/tmp/gfmd_fuzz_topo_XXXXXX";
        const int fd = mkstemp(name);
        if (fd < 0) std::abort();
        close(fd);
        path = name;
    }
    ~Scratch() { unlink(path.c_str()); }
};

const std::string &scratch() {
    static const Scratch file;
    return file.path;
}

void expect(bool ok) {
    if (!ok) std::abort();
}

bool failure(int32_t st) { return st > GFMD_OK && st <= GFMD_ERR_MPI; }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    if (size < 1) return 0;
    const int32_t format = data[0] % (GFMD_TOPO_X3P + 1);
    FILE *f = std::fopen(scratch().c_str(), "wb");
    if (f == nullptr) return 0;
    if (size > 1) std::fwrite(data + 1, 1, size - 1, f);
    std::fclose(f);
    gfmd_topo *t = nullptr;
    char msg[256];
    const int32_t st = gfmd_topo_read(scratch().c_str(), format, 1e-6, &t, msg, sizeof msg);
    if (st != GFMD_OK) {
        expect(failure(st) && t == nullptr && msg[0] != '\0');
        return 0;
    }
    int64_t nx = 0, ny = 0, missing = 0;
    expect(gfmd_topo_get_grid(t, &nx, &ny, nullptr, nullptr) == GFMD_OK && nx >= 1 && ny >= 1);
    expect(gfmd_topo_get_info(t, nullptr, nullptr, &missing) == GFMD_OK);
    if (nx * ny <= 1 << 16) {  // the transforms of what a small input can declare
        const int32_t fill = gfmd_topo_fill_missing(t, data[0] & 1 ? GFMD_FILL_LAPLACE : GFMD_FILL_NEAREST);
        expect(fill == GFMD_OK || fill == GFMD_ERR_STATE);
        const int32_t trend = gfmd_topo_detrend(t, (data[0] >> 1) % 3);
        expect(trend == GFMD_OK || trend == GFMD_ERR_STATE);
        double q[8], c[8], h = 0, s = 0, k = 0;
        int64_t count[8];
        const int32_t psd = gfmd_topo_psd(t, (data[0] >> 3) & 1, 8, q, c, count);
        expect(psd == GFMD_OK || psd == GFMD_ERR_STATE || psd == GFMD_ERR_RANGE);  // RANGE: 1e300 heights
        const int32_t mom = gfmd_topo_moments(t, GFMD_WINDOW_NONE, &h, &s, &k);
        expect(mom == GFMD_OK || mom == GFMD_ERR_STATE || mom == GFMD_ERR_RANGE);
    }
    gfmd_topo_destroy(&t);
    return 0;
}

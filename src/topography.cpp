#include "topography.hpp"

#include <fftw3.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <complex>
#include <cstring>
#include <deque>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <mutex>

#include "constants.hpp"
#include "error.hpp"
#include "fftw_planner.hpp"
#include "gfmd.h"
#include "green.hpp"
#include "least_squares.hpp"
#include "x3p.hpp"

namespace gfmd {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// The largest grid a file may declare: 2^31 points a side, 2^40 points in all (8 TB of doubles);
// the file's length bounds the allocation long before that.
constexpr int64_t kMaxSide = int64_t{1} << 31;

[[noreturn]] void bad(const std::string &what) { fail(GFMD_ERR_FORMAT, what); }

std::string lower(std::string s) {
    for (char &c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

std::string trim(const std::string &s) {
    const char *ws = " \t\r\n";
    const auto a = s.find_first_not_of(ws);
    if (a == std::string::npos) return "";
    return s.substr(a, s.find_last_not_of(ws) - a + 1);
}

// A length unit's size in metres; 0 for an empty or unknown name.
double unit_in_metres(std::string name) {
    name = trim(name);
    static const std::map<std::string, double> units = {
        {"m", 1.0},        {"mm", 1e-3},      {"um", 1e-6},  {"\xc2\xb5m", 1e-6}, {"\xce\xbcm", 1e-6},
        {"micrometer", 1e-6}, {"micron", 1e-6}, {"nm", 1e-9}, {"pm", 1e-12}, {"a", 1e-10},
        {"\xc3\x85", 1e-10}, {"angstrom", 1e-10}, {"cm", 1e-2}};
    const auto it = units.find(lower(name));
    return it == units.end() ? 0.0 : it->second;
}

// A number at the start of [p, end): locale-independent, a leading '+' allowed; "nan" and "bad"
// (any case) are a missing point.  Returns false if the text there is not a number.
bool parse_number(const char *p, const char *end, double &value) {
    if (p < end && *p == '+') ++p;
    const std::size_t len = static_cast<std::size_t>(end - p);
    if ((len == 3 && (lower(std::string(p, 3)) == "nan" || lower(std::string(p, 3)) == "bad"))) {
        value = kNaN;
        return true;
    }
    const auto r = std::from_chars(p, end, value);
    return r.ec == std::errc() && r.ptr == end;
}

void check_finite(double v, const std::string &where) {
    if (std::isinf(v)) bad("an infinite height " + where);
}

int64_t checked_side(double v, const std::string &key) {
    if (!(v >= 1.0 && v <= static_cast<double>(kMaxSide)) || v != std::floor(v))
        bad(key + " must be an integer >= 1, got " + std::to_string(v));
    return static_cast<int64_t>(v);
}

// The data's bytes must be in the file: count values of size bytes from offset (nothing is
// allocated before this holds).
void check_room(const std::string &bytes, uint64_t offset, int64_t nx, int64_t ny, uint64_t size, bool exact,
                const char *format) {
    const uint64_t have = bytes.size() >= offset ? bytes.size() - offset : 0;
    const uint64_t points = static_cast<uint64_t>(nx) * static_cast<uint64_t>(ny);
    if (points > have / size || (exact && points * size != have))
        bad(std::string(format) + ": the header declares " + std::to_string(nx) + " x " + std::to_string(ny) +
            " values of " + std::to_string(size) + " bytes from byte offset " + std::to_string(offset) +
            ", the file holds " + std::to_string(have) + " bytes there");
}

template <class T>
T load_le(const unsigned char *p) {
    T v;
    std::memcpy(&v, p, sizeof v);  // the platform is little-endian (the build checks)
    return v;
}

double load_value(const unsigned char *p, char kind, int size, bool big_endian) {
    unsigned char b[8];
    std::memcpy(b, p, static_cast<std::size_t>(size));
    if (big_endian) std::reverse(b, b + size);
    switch (kind) {
    case 'f': return size == 4 ? static_cast<double>(load_le<float>(b)) : load_le<double>(b);
    case 'i':
        switch (size) {
        case 1: return static_cast<int8_t>(b[0]);
        case 2: return load_le<int16_t>(b);
        case 4: return load_le<int32_t>(b);
        default: return static_cast<double>(load_le<int64_t>(b));
        }
    default:
        switch (size) {
        case 1: return b[0];
        case 2: return load_le<uint16_t>(b);
        case 4: return load_le<uint32_t>(b);
        default: return static_cast<double>(load_le<uint64_t>(b));
        }
    }
}

// ------------------------------------------------------------------------ text: matrix and x y z

struct TextTable {
    std::vector<double> values;
    int64_t columns = 0, rows = 0;
    double width = 0.0, height = 0.0;  // Gwyddion's "# Width:" / "# Height:" in metres (0: absent)
    double value_unit = 0.0;           // "# Value units:" in metres (0: absent)
};

// "<number> <unit>" of a header line, in metres; 0 if the unit is unknown
double header_length(const std::string &text) {
    const std::string t = trim(text);
    const auto sp = t.find_first_of(" \t");
    double v = 0.0;
    if (sp == std::string::npos || !parse_number(t.data(), t.data() + sp, v) || !(v > 0.0)) return 0.0;
    return v * unit_in_metres(t.substr(sp));
}

TextTable parse_table(const std::string &bytes) {
    TextTable t;
    std::size_t pos = 0;
    int64_t line = 0;
    bool data = false;
    while (pos < bytes.size()) {
        std::size_t eol = bytes.find('\n', pos);
        if (eol == std::string::npos) eol = bytes.size();
        const std::string text = bytes.substr(pos, eol - pos);
        pos = eol + 1;
        ++line;
        if (text.find('\0') != std::string::npos) bad("text: a NUL byte on line " + std::to_string(line));
        const std::string s = trim(text);
        if (s.empty()) continue;
        if (s[0] == '#') {
            const std::string key = lower(s);
            const auto colon = s.find(':');
            if (colon != std::string::npos) {
                const std::string name = trim(key.substr(1, colon - 1)), rest = s.substr(colon + 1);
                if (name == "width") t.width = header_length(rest);
                if (name == "height") t.height = header_length(rest);
                if (name == "value units") t.value_unit = unit_in_metres(rest);
            }
            continue;
        }
        // the fields of the line: separated by blanks, commas, semicolons or tabs
        std::vector<double> row;
        const char *p = s.data(), *end = s.data() + s.size();
        bool numeric = true;
        while (p < end) {
            while (p < end && std::strchr(" \t,;\r", *p) != nullptr) ++p;
            if (p == end) break;
            const char *q = p;
            while (q < end && std::strchr(" \t,;\r", *q) == nullptr) ++q;
            double v = 0.0;
            if (!parse_number(p, q, v)) {
                if (data)
                    bad("text: line " + std::to_string(line) + ", field " + std::to_string(row.size() + 1) +
                        ": expected a number, got '" + std::string(p, std::min<std::size_t>(q - p, 40)) + "'");
                numeric = false;
                break;
            }
            check_finite(v, "on line " + std::to_string(line));
            row.push_back(v);
            p = q;
        }
        if (!numeric) continue;  // a header line before the data
        if (row.empty()) continue;  // separators alone (";", ", ,"): a blank line, not a row of 0 values
        if (!data) {
            data = true;
            t.columns = static_cast<int64_t>(row.size());
        } else if (static_cast<int64_t>(row.size()) != t.columns) {
            bad("text: line " + std::to_string(line) + " has " + std::to_string(row.size()) + " values, the first " +
                "data line " + std::to_string(t.columns));
        }
        t.values.insert(t.values.end(), row.begin(), row.end());
        ++t.rows;
    }
    if (t.rows == 0) bad("text: no line of numbers found");
    return t;
}

// Three columns whose first two take evenly spaced values that make a grid: an x y z listing.
bool is_xyz(const TextTable &t, std::vector<double> &xs, std::vector<double> &ys) {
    if (t.columns != 3 || t.rows < 4) return false;
    xs.clear();
    ys.clear();
    for (int64_t r = 0; r < t.rows; ++r) {
        const double x = t.values[static_cast<std::size_t>(3 * r)], y = t.values[static_cast<std::size_t>(3 * r + 1)];
        if (std::isnan(x) || std::isnan(y)) return false;
        xs.push_back(x);
        ys.push_back(y);
    }
    const auto grid_of = [](std::vector<double> &v) {
        std::sort(v.begin(), v.end());
        v.erase(std::unique(v.begin(), v.end()), v.end());
        if (v.size() < 2) return false;
        const double d = (v.back() - v.front()) / static_cast<double>(v.size() - 1);
        for (std::size_t i = 0; i < v.size(); ++i)
            if (std::abs(v[i] - (v.front() + d * static_cast<double>(i))) > 1e-6 * d) return false;
        return true;
    };
    if (!grid_of(xs) || !grid_of(ys)) return false;
    // a scan's listing: at least half of its grid present (so the grid allocated is bounded by the
    // file's length: a diagonal line of n points would make an n x n grid)
    const double grid = static_cast<double>(xs.size()) * static_cast<double>(ys.size());
    return grid >= static_cast<double>(t.rows) && grid <= 2.0 * static_cast<double>(t.rows);
}

Topography from_table(const std::string &bytes, int32_t format, double unit) {
    TextTable t = parse_table(bytes);
    Topography out;
    std::vector<double> xs, ys;
    const bool xyz = is_xyz(t, xs, ys);
    if (format == GFMD_TOPO_XYZ && !xyz)
        bad("x y z: expected three columns whose x and y make an evenly spaced grid, at least half of it listed");
    if (format == GFMD_TOPO_XYZ || (format == GFMD_TOPO_AUTO && xyz)) {
        out.format = GFMD_TOPO_XYZ;
        out.nx = static_cast<int64_t>(xs.size());
        out.ny = static_cast<int64_t>(ys.size());
        const double dx = (xs.back() - xs.front()) / static_cast<double>(out.nx - 1);
        const double dy = (ys.back() - ys.front()) / static_cast<double>(out.ny - 1);
        out.lx = dx * static_cast<double>(out.nx);
        out.ly = dy * static_cast<double>(out.ny);
        out.h.assign(static_cast<std::size_t>(out.nx * out.ny), kNaN);  // <= 3 values a row: bounded
        for (int64_t r = 0; r < t.rows; ++r) {
            const double *v = &t.values[static_cast<std::size_t>(3 * r)];
            const auto ix = static_cast<int64_t>(std::llround((v[0] - xs.front()) / dx));
            const auto iy = static_cast<int64_t>(std::llround((v[1] - ys.front()) / dy));
            double &slot = out.h[static_cast<std::size_t>(iy * out.nx + ix)];
            if (!std::isnan(slot))
                bad("x y z: line " + std::to_string(r + 1) + " repeats the point (" + std::to_string(v[0]) + ", " +
                    std::to_string(v[1]) + ")");
            slot = v[2];
        }
        return out;  // no units in the file: lengths and heights as they are
    }
    out.format = GFMD_TOPO_MATRIX;
    out.nx = t.columns;
    out.ny = t.rows;
    out.h = std::move(t.values);
    if (t.width > 0.0 && t.height > 0.0) {
        out.has_units = true;
        out.lx = t.width / unit;
        out.ly = t.height / unit;
        const double z = t.value_unit > 0.0 ? t.value_unit : 1.0;  // Gwyddion writes heights in metres
        for (double &v : out.h) v *= z / unit;
    } else {
        out.lx = static_cast<double>(out.nx);
        out.ly = static_cast<double>(out.ny);
    }
    return out;
}

// ------------------------------------------------------------------------ Gwyddion simple field

Topography from_gsf(const std::string &bytes, double unit) {
    const std::string magic = "Gwyddion Simple Field 1.0\n";
    if (bytes.compare(0, magic.size(), magic) != 0) bad("gsf: expected the line 'Gwyddion Simple Field 1.0'");
    const std::size_t nul = bytes.find('\0');
    if (nul == std::string::npos) bad("gsf: the header is not ended by NUL padding (truncated?)");
    std::map<std::string, std::string> keys;
    std::size_t pos = magic.size();
    while (pos < nul) {
        std::size_t eol = bytes.find('\n', pos);
        if (eol == std::string::npos || eol > nul) eol = nul;
        const std::string s = trim(bytes.substr(pos, eol - pos));
        pos = eol + 1;
        if (s.empty()) continue;
        const auto eq = s.find('=');
        if (eq == std::string::npos) bad("gsf: header line '" + s.substr(0, 40) + "' has no '='");
        keys[trim(s.substr(0, eq))] = trim(s.substr(eq + 1));
    }
    const auto number = [&](const char *key, double fallback, bool required) {
        const auto it = keys.find(key);
        if (it == keys.end()) {
            if (required) bad(std::string("gsf: the header has no ") + key);
            return fallback;
        }
        double v = 0.0;
        if (!parse_number(it->second.data(), it->second.data() + it->second.size(), v) || !std::isfinite(v))
            bad(std::string("gsf: ") + key + " = '" + it->second.substr(0, 40) + "' is not a finite number");
        return v;
    };
    Topography out;
    out.format = GFMD_TOPO_GSF;
    out.nx = checked_side(number("XRes", 0, true), "gsf: XRes");
    out.ny = checked_side(number("YRes", 0, true), "gsf: YRes");
    const double xreal = number("XReal", static_cast<double>(out.nx), false);
    const double yreal = number("YReal", static_cast<double>(out.ny), false);
    if (!(xreal > 0.0) || !(yreal > 0.0)) bad("gsf: XReal and YReal must be > 0");
    // NUL padding to a multiple of 4 bytes: 1 to 4 of them
    const std::size_t data = nul + (4 - nul % 4);
    for (std::size_t i = nul; i < data; ++i)
        if (i >= bytes.size() || bytes[i] != '\0') bad("gsf: expected NUL padding at byte offset " + std::to_string(i));
    check_room(bytes, data, out.nx, out.ny, 4, true, "gsf");
    const double xy = keys.count("XYUnits") ? unit_in_metres(keys["XYUnits"]) : 0.0;
    const double z = keys.count("ZUnits") ? unit_in_metres(keys["ZUnits"]) : 0.0;
    if (keys.count("XYUnits") && xy == 0.0) bad("gsf: unknown length unit XYUnits = '" + keys["XYUnits"] + "'");
    if (keys.count("ZUnits") && z == 0.0) bad("gsf: unknown length unit ZUnits = '" + keys["ZUnits"] + "'");
    out.has_units = xy > 0.0 && z > 0.0;
    const double sxy = out.has_units ? xy / unit : 1.0, sz = out.has_units ? z / unit : 1.0;
    out.lx = xreal * sxy;
    out.ly = yreal * sxy;
    out.h.resize(static_cast<std::size_t>(out.nx * out.ny));
    const auto *p = reinterpret_cast<const unsigned char *>(bytes.data()) + data;
    for (std::size_t i = 0; i < out.h.size(); ++i) {
        const double v = load_value(p + 4 * i, 'f', 4, false);
        check_finite(v, "at point " + std::to_string(i));
        out.h[i] = v * sz;
    }
    return out;
}

// ------------------------------------------------------------------------ ISO 25178-71 / BCR (SDF)

// data types 0-7: uint8, uint16, uint32, float, int8, int16, int32, double
struct SdfType {
    char kind;
    int size;
    double bad;  // the value that marks a missing point (NaN: none but NaN itself)
};
const SdfType kSdfTypes[8] = {{'u', 1, kNaN}, {'u', 2, 65535.0}, {'u', 4, 4294967295.0}, {'f', 4, kNaN},
                              {'i', 1, kNaN}, {'i', 2, -32768.0}, {'i', 4, -2147483648.0}, {'f', 8, kNaN}};

struct SdfHeader {
    int64_t nx = 0, ny = 0;
    double xscale = 0, yscale = 0, zscale = 0;
    int type = 0;
};

void sdf_check(const SdfHeader &s, int compression, int check) {
    if (compression != 0) bad("sdf: Compression = " + std::to_string(compression) + " (only 0, uncompressed, is read)");
    if (check != 0) bad("sdf: CheckType = " + std::to_string(check) + " (only 0 is read)");
    if (s.type < 0 || s.type > 7) bad("sdf: DataType = " + std::to_string(s.type) + ", expected 0 to 7");
    if (!(std::isfinite(s.xscale) && s.xscale > 0.0 && std::isfinite(s.yscale) && s.yscale > 0.0))
        bad("sdf: Xscale and Yscale must be finite and > 0");
    if (!(std::isfinite(s.zscale) && s.zscale != 0.0)) bad("sdf: Zscale must be finite and nonzero");
}

Topography sdf_topography(const SdfHeader &s, double unit, int32_t format) {
    Topography out;
    out.format = format;
    out.nx = s.nx;
    out.ny = s.ny;
    out.has_units = true;  // the standard's unit is the metre
    out.lx = static_cast<double>(s.nx) * s.xscale / unit;
    out.ly = static_cast<double>(s.ny) * s.yscale / unit;
    return out;
}

Topography from_sdf_binary(const std::string &bytes, double unit) {
    constexpr std::size_t kHeader = 8 + 10 + 12 + 12 + 2 + 2 + 4 * 8 + 3;
    if (bytes.size() < kHeader)
        bad("sdf: the binary header needs " + std::to_string(kHeader) + " bytes, the file has " +
            std::to_string(bytes.size()));
    const auto *p = reinterpret_cast<const unsigned char *>(bytes.data());
    SdfHeader s;
    s.nx = load_le<uint16_t>(p + 42);
    s.ny = load_le<uint16_t>(p + 44);
    s.xscale = load_le<double>(p + 46);
    s.yscale = load_le<double>(p + 54);
    s.zscale = load_le<double>(p + 62);
    s.type = p[79];
    const int compression = p[78], check = p[80];
    if (s.nx < 1 || s.ny < 1) bad("sdf: NumPoints and NumProfiles must be >= 1");
    sdf_check(s, compression, check);
    const SdfType ty = kSdfTypes[s.type];
    check_room(bytes, kHeader, s.nx, s.ny, static_cast<uint64_t>(ty.size), false, "sdf");  // a trailer may follow
    Topography out = sdf_topography(s, unit, GFMD_TOPO_SDF_BINARY);
    out.h.resize(static_cast<std::size_t>(s.nx * s.ny));
    for (std::size_t i = 0; i < out.h.size(); ++i) {
        const double v = load_value(p + kHeader + static_cast<std::size_t>(ty.size) * i, ty.kind, ty.size, false);
        check_finite(v, "at point " + std::to_string(i));
        out.h[i] = (v == ty.bad || std::isnan(v)) ? kNaN : v * s.zscale / unit;
    }
    return out;
}

Topography from_sdf_text(const std::string &bytes, double unit) {
    std::map<std::string, std::string> keys;
    std::size_t pos = bytes.find('\n');
    if (pos == std::string::npos) bad("sdf: the text header is truncated after its first line");
    ++pos;
    int64_t line = 1;
    bool star = false;
    while (pos < bytes.size()) {
        std::size_t eol = bytes.find('\n', pos);
        if (eol == std::string::npos) eol = bytes.size();
        const std::string s = trim(bytes.substr(pos, eol - pos));
        pos = eol + 1;
        ++line;
        if (s == "*") {
            star = true;
            break;
        }
        if (s.empty() || s[0] == ';') continue;
        const auto eq = s.find('=');
        if (eq == std::string::npos) bad("sdf: line " + std::to_string(line) + " of the header has no '='");
        keys[lower(trim(s.substr(0, eq)))] = trim(s.substr(eq + 1));
    }
    if (!star) bad("sdf: the header's end marker '*' is missing (truncated?)");
    const auto number = [&](const char *key, bool required) {
        const auto it = keys.find(lower(key));
        if (it == keys.end()) {
            if (required) bad(std::string("sdf: the header has no ") + key);
            return 0.0;
        }
        double v = 0.0;
        if (!parse_number(it->second.data(), it->second.data() + it->second.size(), v) || std::isnan(v))
            bad(std::string("sdf: ") + key + " = '" + it->second.substr(0, 40) + "' is not a number");
        return v;
    };
    SdfHeader s;
    s.nx = checked_side(number("NumPoints", true), "sdf: NumPoints");
    s.ny = checked_side(number("NumProfiles", true), "sdf: NumProfiles");
    s.xscale = number("Xscale", true);
    s.yscale = number("Yscale", true);
    s.zscale = number("Zscale", true);
    // small integer codes: anything else (1e10, 2.5) is one the checks below refuse
    const auto code = [&](const char *key, double fallback) {
        const double v = keys.count(lower(key)) ? number(key, false) : fallback;
        return (v >= 0.0 && v <= 255.0 && v == std::floor(v)) ? static_cast<int>(v) : 256;
    };
    s.type = code("DataType", 7);
    sdf_check(s, code("Compression", 0), code("CheckType", 0));
    // every value takes at least 2 bytes of text: the count declared must fit in the file
    if (static_cast<uint64_t>(s.nx) * static_cast<uint64_t>(s.ny) > (bytes.size() - std::min(pos, bytes.size())) / 2 + 1)
        bad("sdf: the header declares " + std::to_string(s.nx) + " x " + std::to_string(s.ny) +
            " values, more than the file's remaining " + std::to_string(bytes.size() - std::min(pos, bytes.size())) +
            " bytes can hold");
    Topography out = sdf_topography(s, unit, GFMD_TOPO_SDF_TEXT);
    const auto points = static_cast<std::size_t>(s.nx * s.ny);
    out.h.reserve(points);
    const char *p = bytes.data() + std::min(pos, bytes.size()), *end = bytes.data() + bytes.size();
    while (p < end) {
        while (p < end && std::strchr(" \t\r\n,", *p) != nullptr) ++p;
        if (p == end || *p == '*') break;  // the trailer's marker
        const char *q = p;
        while (q < end && std::strchr(" \t\r\n,", *q) == nullptr) ++q;
        double v = 0.0;
        if (!parse_number(p, q, v))
            bad("sdf: value " + std::to_string(out.h.size() + 1) + " at byte offset " +
                std::to_string(p - bytes.data()) + ": expected a number, got '" +
                std::string(p, std::min<std::ptrdiff_t>(q - p, 40)) + "'");
        check_finite(v, "at value " + std::to_string(out.h.size() + 1));
        if (out.h.size() == points) bad("sdf: more values than NumPoints x NumProfiles = " + std::to_string(points));
        out.h.push_back(std::isnan(v) ? kNaN : v * s.zscale / unit);
        p = q;
    }
    if (out.h.size() != points)
        bad("sdf: " + std::to_string(out.h.size()) + " values, the header declares " + std::to_string(points));
    return out;
}

// ------------------------------------------------------------------------ numpy .npy

Topography from_npy(const std::string &bytes, double unit) {
    (void)unit;  // .npy carries no units
    if (bytes.size() < 10) bad("npy: shorter than its 10-byte preamble");
    const auto *p = reinterpret_cast<const unsigned char *>(bytes.data());
    const int major = p[6];
    std::size_t header_len = 0, start = 0;
    if (major == 1) {
        header_len = load_le<uint16_t>(p + 8);
        start = 10;
    } else if (major == 2 || major == 3) {
        if (bytes.size() < 12) bad("npy: shorter than its 12-byte preamble");
        header_len = load_le<uint32_t>(p + 8);
        start = 12;
    } else {
        bad("npy: format version " + std::to_string(major) + ", expected 1, 2 or 3");
    }
    if (header_len > bytes.size() - start)
        bad("npy: the header claims " + std::to_string(header_len) + " bytes, the file has " +
            std::to_string(bytes.size() - start) + " after the preamble");
    const std::string h = bytes.substr(start, header_len);
    const auto value_of = [&](const char *key) {
        const auto k = h.find(std::string("'") + key + "'");
        if (k == std::string::npos) bad(std::string("npy: the header has no '") + key + "'");
        const auto colon = h.find(':', k);
        if (colon == std::string::npos) bad(std::string("npy: no ':' after '") + key + "'");
        return trim(h.substr(colon + 1));
    };
    std::string descr = value_of("descr");
    if (descr.size() < 4 || (descr[0] != '\'' && descr[0] != '"')) bad("npy: 'descr' is not a string");
    descr = descr.substr(1, descr.find(descr[0], 1) - 1);
    if (descr.size() < 3) bad("npy: unsupported dtype '" + descr + "'");
    const char order = descr[0], kind = descr[1];
    const std::string digits = descr.substr(2);
    const int size = digits == "1" || digits == "2" || digits == "4" || digits == "8" ? digits[0] - '0' : 0;
    const bool ok_kind = (kind == 'f' && (size == 4 || size == 8)) ||
                         ((kind == 'i' || kind == 'u') && (size == 1 || size == 2 || size == 4 || size == 8));
    if (!ok_kind || std::strchr("<>|=", order) == nullptr)
        bad("npy: dtype '" + descr + "', expected a float (f4, f8) or an integer (i1-i8, u1-u8)");
    const bool fortran = value_of("fortran_order").rfind("True", 0) == 0;
    const std::string shape = value_of("shape");
    if (shape.empty() || shape[0] != '(') bad("npy: 'shape' is not a tuple");
    std::vector<int64_t> dims;
    std::size_t i = 1;
    while (i < shape.size() && shape[i] != ')') {
        while (i < shape.size() && (shape[i] == ' ' || shape[i] == ',')) ++i;
        if (i < shape.size() && shape[i] == ')') break;
        std::size_t j = i;
        while (j < shape.size() && std::isdigit(static_cast<unsigned char>(shape[j]))) ++j;
        if (j == i) bad("npy: 'shape' holds something other than integers");
        dims.push_back(checked_side(static_cast<double>(std::strtoll(shape.substr(i, j - i).c_str(), nullptr, 10)),
                                    "npy: a dimension"));
        i = j;
    }
    if (dims.size() != 2) bad("npy: a " + std::to_string(dims.size()) + "-dimensional array, expected 2 (ny, nx)");
    Topography out;
    out.format = GFMD_TOPO_NPY;
    out.ny = dims[0];
    out.nx = dims[1];
    out.lx = static_cast<double>(out.nx);
    out.ly = static_cast<double>(out.ny);
    const uint64_t data = start + header_len;
    check_room(bytes, data, out.nx, out.ny, static_cast<uint64_t>(size), true, "npy");
    out.h.resize(static_cast<std::size_t>(out.nx * out.ny));
    const auto *d = p + data;
    for (int64_t y = 0; y < out.ny; ++y)
        for (int64_t x = 0; x < out.nx; ++x) {
            const int64_t k = fortran ? x * out.ny + y : y * out.nx + x;
            const double v = load_value(d + static_cast<std::size_t>(k) * static_cast<std::size_t>(size), kind, size,
                                        order == '>');
            check_finite(v, "at element " + std::to_string(k));
            out.h[static_cast<std::size_t>(y * out.nx + x)] = v;
        }
    return out;
}

int32_t detect(const std::string &bytes) {
    if (bytes.compare(0, 6, "\x93NUMPY") == 0) return GFMD_TOPO_NPY;
    if (looks_like_zip(bytes)) return GFMD_TOPO_X3P;
    if (bytes.compare(0, 21, "Gwyddion Simple Field") == 0) return GFMD_TOPO_GSF;
    if (bytes.size() >= 8 && (bytes.compare(1, 4, "BCR-") == 0 || bytes.compare(1, 4, "ISO-") == 0)) {
        if (bytes[0] == 'a') return GFMD_TOPO_SDF_TEXT;
        if (bytes[0] == 'b') return GFMD_TOPO_SDF_BINARY;
    }
    return GFMD_TOPO_MATRIX;  // text: a matrix or an x y z listing, told apart by its columns
}

// ------------------------------------------------------------------------ spectra

struct Spectrum {
    int64_t nx, ny, nxh;
    std::vector<std::complex<double>> hq;  // normalized (h(r) = sum_q h_q e^{iqr}) of h / scale
    double scale;                          // the largest |h|: the transform never overflows
};

void need_complete(const Topography &t) {
    const int64_t m = t.missing();
    if (m > 0)
        fail(GFMD_ERR_STATE, std::to_string(m) + " missing points: fill them first (gfmd_topo_fill_missing)");
}

void check_window(int32_t window) {
    if (window != GFMD_WINDOW_NONE && window != GFMD_WINDOW_HANN)
        fail(GFMD_ERR_BAD_ENUM, "unknown window " + std::to_string(window));
}

// w(i) = sin^2(pi (i + 1/2) / n), scaled to a mean square of 1 (the windowed heights keep their
// rms height on average)
std::vector<double> hann(int64_t n) {
    std::vector<double> w(static_cast<std::size_t>(n));
    double s = 0.0;
    for (int64_t i = 0; i < n; ++i) {
        const double v = std::sin(kPi * (static_cast<double>(i) + 0.5) / static_cast<double>(n));
        w[static_cast<std::size_t>(i)] = v * v;
        s += v * v * v * v;
    }
    const double k = 1.0 / std::sqrt(s / static_cast<double>(n));
    for (double &v : w) v *= k;
    return w;
}

// The mean-free (windowed) heights' transform over rows of length nx, ny rows (ny = 1 with rank 1)
Spectrum transform(const Topography &t, int32_t window, bool profiles) {
    need_complete(t);
    check_window(window);
    Spectrum s{t.nx, t.ny, t.nx / 2 + 1, {}, 0.0};
    for (double v : t.h) s.scale = std::max(s.scale, std::abs(v));
    if (!(s.scale > 0.0)) s.scale = 1.0;
    if (!(2.0 * kPi / t.lx * static_cast<double>(t.nx) < 1e150 && 2.0 * kPi / t.ly * static_cast<double>(t.ny) < 1e150))
        fail(GFMD_ERR_RANGE, "the grid's wavevectors overflow: the physical size is too small");
    std::vector<double> in(t.h);
    for (double &v : in) v /= s.scale;
    const auto rows = static_cast<std::size_t>(t.ny), cols = static_cast<std::size_t>(t.nx);
    // the mean removed first (of each profile for the profiles' spectrum), then the window
    const auto remove_mean = [&](std::size_t begin, std::size_t count) {
        double m = 0.0;
        for (std::size_t i = 0; i < count; ++i) m += in[begin + i];
        m /= static_cast<double>(count);
        for (std::size_t i = 0; i < count; ++i) in[begin + i] -= m;
    };
    if (profiles)
        for (std::size_t y = 0; y < rows; ++y) remove_mean(y * cols, cols);
    else
        remove_mean(0, in.size());
    if (window == GFMD_WINDOW_HANN) {
        const std::vector<double> wx = hann(t.nx), wy = profiles ? std::vector<double>(rows, 1.0) : hann(t.ny);
        for (std::size_t y = 0; y < rows; ++y)
            for (std::size_t x = 0; x < cols; ++x) in[y * cols + x] *= wx[x] * wy[y];
        if (!profiles) remove_mean(0, in.size());
    }
    s.hq.resize(rows * static_cast<std::size_t>(s.nxh));
    fftw_plan plan = nullptr;
    {
        std::lock_guard<std::mutex> lock(planner_mutex());
        if (threads_ready()) fftw_plan_with_nthreads(1);  // one thread: FFTW's count is the last plan's
        WisdomAside aside(true);
        auto *out = reinterpret_cast<fftw_complex *>(s.hq.data());
        if (profiles) {
            const int n[1] = {static_cast<int>(t.nx)};
            plan = fftw_plan_many_dft_r2c(1, n, static_cast<int>(t.ny), in.data(), nullptr, 1, static_cast<int>(t.nx),
                                          out, nullptr, 1, static_cast<int>(s.nxh), FFTW_ESTIMATE);
        } else {
            plan = fftw_plan_dft_r2c_2d(static_cast<int>(t.ny), static_cast<int>(t.nx), in.data(), out, FFTW_ESTIMATE);
        }
    }
    if (plan == nullptr) throw std::bad_alloc();
    fftw_execute(plan);
    {
        std::lock_guard<std::mutex> lock(planner_mutex());
        fftw_destroy_plan(plan);
    }
    const double inv = 1.0 / static_cast<double>(profiles ? t.nx : t.nx * t.ny);
    for (auto &c : s.hq) c *= inv;
    return s;
}

// every mode of the full plane but q = 0, with its weight (1 or 2: the half spectrum's
// conjugate partner), |q|^2 and |h_q|^2
template <class F>
void for_each_mode(const Topography &t, const Spectrum &s, F &&f) {
    for (int64_t ky = 0; ky < t.ny; ++ky) {
        const int64_t sy = ky <= t.ny / 2 ? ky : ky - t.ny;
        const double qy = 2.0 * kPi * static_cast<double>(sy) / t.ly;
        for (int64_t kx = 0; kx < s.nxh; ++kx) {
            if (kx == 0 && ky == 0) continue;
            const double qx = 2.0 * kPi * static_cast<double>(kx) / t.lx;
            const double w = (kx == 0 || (t.nx % 2 == 0 && kx == t.nx / 2)) ? 1.0 : 2.0;
            f(w, qx * qx + qy * qy, std::norm(s.hq[static_cast<std::size_t>(ky * s.nxh + kx)]));
        }
    }
}

}  // namespace

int64_t Topography::missing() const {
    return static_cast<int64_t>(std::count_if(h.begin(), h.end(), [](double v) { return std::isnan(v); }));
}

Topography parse_topography(const std::string &bytes, int32_t format, double unit) {
    if (!(std::isfinite(unit) && unit > 0.0)) fail(GFMD_ERR_INVALID_ARG, "unit must be a finite length > 0 in metres");
    if (format < GFMD_TOPO_AUTO || format > GFMD_TOPO_X3P) fail(GFMD_ERR_BAD_ENUM, "unknown topography format");
    const int32_t f = format == GFMD_TOPO_AUTO ? detect(bytes) : format;
    Topography t;
    switch (f) {
    case GFMD_TOPO_GSF: t = from_gsf(bytes, unit); break;
    case GFMD_TOPO_SDF_TEXT: t = from_sdf_text(bytes, unit); break;
    case GFMD_TOPO_SDF_BINARY: t = from_sdf_binary(bytes, unit); break;
    case GFMD_TOPO_NPY: t = from_npy(bytes, unit); break;
    case GFMD_TOPO_X3P: t = from_x3p(bytes, unit); break;
    default: t = from_table(bytes, format, unit); break;
    }
    // the unit conversion may overflow what the file's numbers did not
    if (!(std::isfinite(t.lx) && t.lx > 0.0 && std::isfinite(t.ly) && t.ly > 0.0))
        bad("the physical size " + std::to_string(t.lx) + " x " + std::to_string(t.ly) +
            " (in the caller's unit) is not finite and > 0");
    for (std::size_t i = 0; i < t.h.size(); ++i)
        if (std::isinf(t.h[i])) bad("the height at point " + std::to_string(i) + " overflows in the caller's unit");
    return t;
}

Topography read_topography(const std::string &path, int32_t format, double unit) {
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) fail(GFMD_ERR_IO, "cannot open '" + path + "' for reading");
    const std::streamoff size = in.tellg();
    if (size < 0) fail(GFMD_ERR_IO, "cannot read the length of '" + path + "'");
    std::string bytes(static_cast<std::size_t>(size), '\0');
    in.seekg(0);
    if (!in.read(bytes.data(), size)) fail(GFMD_ERR_IO, "cannot read '" + path + "'");
    try {
        return parse_topography(bytes, format, unit);
    } catch (const Error &e) {
        fail(e.status(), e.status() == GFMD_ERR_FORMAT ? "'" + path + "': " + e.what() : e.what());
    }
}

Topography topography_from_heights(int64_t nx, int64_t ny, double lx, double ly, const double *h) {
    if (nx < 1 || ny < 1 || nx > kMaxSide || ny > kMaxSide)
        fail(GFMD_ERR_INVALID_ARG, "nx and ny must be >= 1 and <= 2^31");
    if (!(std::isfinite(lx) && lx > 0.0 && std::isfinite(ly) && ly > 0.0))
        fail(GFMD_ERR_INVALID_ARG, "lx and ly must be finite and > 0");
    Topography t;
    t.nx = nx;
    t.ny = ny;
    t.lx = lx;
    t.ly = ly;
    t.format = GFMD_TOPO_AUTO;  // not from a file
    t.h.assign(h, h + nx * ny);
    for (std::size_t i = 0; i < t.h.size(); ++i)
        if (std::isinf(t.h[i])) fail(GFMD_ERR_INVALID_ARG, "heights[" + std::to_string(i) + "] is infinite (NaN marks a missing point)");
    return t;
}

void fill_missing(Topography &t, int32_t method) {
    if (method != GFMD_FILL_NEAREST && method != GFMD_FILL_LAPLACE)
        fail(GFMD_ERR_BAD_ENUM, "unknown fill method " + std::to_string(method));
    const int64_t m = t.missing(), n = t.nx * t.ny;
    if (m == 0) return;
    if (m == n) fail(GFMD_ERR_STATE, "every point is missing: nothing to fill from");
    std::vector<double> h = t.h;
    const auto neighbours = [&](int64_t i, auto &&f) {
        const int64_t x = i % t.nx, y = i / t.nx;
        if (x > 0) f(i - 1);
        if (x + 1 < t.nx) f(i + 1);
        if (y > 0) f(i - t.nx);
        if (y + 1 < t.ny) f(i + t.nx);
    };
    // nearest: a breadth-first sweep from every measured point at once (4-neighbour steps, in
    // index order within each distance): a missing point takes the value of the first measured
    // point to reach it
    std::deque<int64_t> queue;
    for (int64_t i = 0; i < n; ++i)
        if (!std::isnan(h[static_cast<std::size_t>(i)])) queue.push_back(i);
    while (!queue.empty()) {
        const int64_t i = queue.front();
        queue.pop_front();
        neighbours(i, [&](int64_t j) {
            if (std::isnan(h[static_cast<std::size_t>(j)])) {
                h[static_cast<std::size_t>(j)] = h[static_cast<std::size_t>(i)];
                queue.push_back(j);
            }
        });
    }
    if (method == GFMD_FILL_LAPLACE) {
        // The harmonic fill: the 5-point Laplacian zero at every missing point, the measured ones
        // fixed, no flux through the scan's border.  Conjugate gradients on the missing points
        // (symmetric positive definite: every missing region touches a measured point), from the
        // nearest fill, to a residual of 1e-13 of the right-hand side's.
        std::vector<int64_t> index(static_cast<std::size_t>(n), -1), at;
        for (int64_t i = 0; i < n; ++i)
            if (std::isnan(t.h[static_cast<std::size_t>(i)])) {
                index[static_cast<std::size_t>(i)] = static_cast<int64_t>(at.size());
                at.push_back(i);
            }
        const auto k = at.size();
        // in units of the largest |h|: the sums below never overflow
        double scale = 0.0;
        for (double v : h) scale = std::max(scale, std::abs(v));
        if (!(scale > 0.0)) scale = 1.0;
        std::vector<double> x(k), b(k, 0.0), r(k), p(k), ap(k);
        for (std::size_t a = 0; a < k; ++a) {
            x[a] = h[static_cast<std::size_t>(at[a])] / scale;
            neighbours(at[a], [&](int64_t j) {
                if (index[static_cast<std::size_t>(j)] < 0) b[a] += t.h[static_cast<std::size_t>(j)] / scale;
            });
        }
        const auto apply = [&](const std::vector<double> &v, std::vector<double> &out) {
            for (std::size_t a = 0; a < k; ++a) {
                double s = 0.0, deg = 0.0;
                neighbours(at[a], [&](int64_t j) {
                    deg += 1.0;
                    const int64_t c = index[static_cast<std::size_t>(j)];
                    if (c >= 0) s += v[static_cast<std::size_t>(c)];
                });
                out[a] = deg * v[a] - s;
            }
        };
        apply(x, ap);
        double rr = 0.0, bb = 0.0;
        for (std::size_t a = 0; a < k; ++a) {
            r[a] = b[a] - ap[a];
            p[a] = r[a];
            rr += r[a] * r[a];
            bb += b[a] * b[a];
        }
        const double goal = 1e-26 * std::max(bb, std::numeric_limits<double>::min());
        const int64_t limit = 20 * static_cast<int64_t>(k) + 100;
        for (int64_t it = 0; it < limit && rr > goal; ++it) {
            apply(p, ap);
            double pap = 0.0;
            for (std::size_t a = 0; a < k; ++a) pap += p[a] * ap[a];
            const double alpha = rr / pap;
            double next = 0.0;
            for (std::size_t a = 0; a < k; ++a) {
                x[a] += alpha * p[a];
                r[a] -= alpha * ap[a];
                next += r[a] * r[a];
            }
            for (std::size_t a = 0; a < k; ++a) p[a] = r[a] + next / rr * p[a];
            rr = next;
        }
        if (!(rr <= goal)) fail(GFMD_ERR_NOT_CONVERGED, "the Laplace fill did not converge");
        for (std::size_t a = 0; a < k; ++a) h[static_cast<std::size_t>(at[a])] = x[a] * scale;
    }
    t.h.swap(h);
}

void detrend(Topography &t, int32_t mode) {
    if (mode != GFMD_DETREND_HEIGHT && mode != GFMD_DETREND_PLANE && mode != GFMD_DETREND_CURVATURE)
        fail(GFMD_ERR_BAD_ENUM, "unknown detrend mode " + std::to_string(mode));
    const int terms = mode == GFMD_DETREND_HEIGHT ? 1 : mode == GFMD_DETREND_PLANE ? 3 : 6;
    std::vector<int64_t> valid;
    for (int64_t i = 0; i < t.nx * t.ny; ++i)
        if (!std::isnan(t.h[static_cast<std::size_t>(i)])) valid.push_back(i);
    const auto m = static_cast<int64_t>(valid.size());
    if (m < terms) fail(GFMD_ERR_STATE, "too few measured points for the fit");
    // x and y scaled to [-1, 1] over the grid: a well-conditioned basis 1, x, y, x^2, x y, y^2
    const auto basis = [&](int64_t i, double *row) {
        const double x = t.nx > 1 ? 2.0 * static_cast<double>(i % t.nx) / static_cast<double>(t.nx - 1) - 1.0 : 0.0;
        const double y = t.ny > 1 ? 2.0 * static_cast<double>(i / t.nx) / static_cast<double>(t.ny - 1) - 1.0 : 0.0;
        const double all[6] = {1.0, x, y, x * x, x * y, y * y};
        std::copy(all, all + terms, row);
    };
    std::vector<double> a(static_cast<std::size_t>(m * terms)), b(static_cast<std::size_t>(m)), row(6);
    for (int64_t r = 0; r < m; ++r) {
        basis(valid[static_cast<std::size_t>(r)], row.data());
        for (int c = 0; c < terms; ++c) a[static_cast<std::size_t>(c * m + r)] = row[static_cast<std::size_t>(c)];
        b[static_cast<std::size_t>(r)] = t.h[static_cast<std::size_t>(valid[static_cast<std::size_t>(r)])];
    }
    double coef[6] = {0, 0, 0, 0, 0, 0};
    try {
        least_squares(m, terms, a.data(), b.data(), coef);
    } catch (const Error &) {
        fail(GFMD_ERR_STATE, "the measured points do not determine the fit (too few rows or columns)");
    }
    std::vector<double> h = t.h;
    for (int64_t i : valid) {
        basis(i, row.data());
        double fit = 0.0;
        for (int c = 0; c < terms; ++c) fit += coef[c] * row[static_cast<std::size_t>(c)];
        h[static_cast<std::size_t>(i)] -= fit;
    }
    t.h.swap(h);
}

namespace {

// Keys' cubic convolution kernel, a = -1/2
double keys(double s) {
    s = std::abs(s);
    if (s <= 1.0) return (1.5 * s - 2.5) * s * s + 1.0;
    if (s < 2.0) return ((-0.5 * s + 2.5) * s - 4.0) * s + 2.0;
    return 0.0;
}

// v (n values, stride) at m points spanning the same extent, into out (m values, stride)
void resample_line(const double *v, int64_t n, int64_t stride, int64_t m, double *out, int64_t out_stride) {
    const double step = static_cast<double>(n - 1) / static_cast<double>(m - 1);
    for (int64_t j = 0; j < m; ++j) {
        const double x = j == m - 1 ? static_cast<double>(n - 1) : static_cast<double>(j) * step;
        const auto i0 = static_cast<int64_t>(std::floor(x));
        double sum = 0.0;
        for (int64_t i = i0 - 1; i <= i0 + 2; ++i) {
            const int64_t c = std::min(std::max<int64_t>(i, 0), n - 1);  // the border sample continued
            sum += keys(x - static_cast<double>(i)) * v[c * stride];
        }
        out[j * out_stride] = sum;
    }
}

}  // namespace

void resample(Topography &t, int64_t nx, int64_t ny) {
    if (nx < 2 || ny < 2 || nx > kMaxSide || ny > kMaxSide || nx > (int64_t{1} << 40) / ny)
        fail(GFMD_ERR_INVALID_ARG, "the new grid needs 2..2^31 points a side (and at most 2^40 in all)");
    if (t.nx < 2 || t.ny < 2) fail(GFMD_ERR_STATE, "a topography of one row or column cannot be resampled");
    need_complete(t);
    std::vector<double> rows(static_cast<std::size_t>(nx * t.ny)), out(static_cast<std::size_t>(nx * ny));
    for (int64_t y = 0; y < t.ny; ++y)
        resample_line(t.h.data() + y * t.nx, t.nx, 1, nx, rows.data() + y * nx, 1);
    for (int64_t x = 0; x < nx; ++x) resample_line(rows.data() + x, t.ny, nx, ny, out.data() + x, nx);
    // the samples' extent kept: (n - 1) spacings before, (n' - 1) after
    const double lx = t.lx / static_cast<double>(t.nx) * static_cast<double>(t.nx - 1) / static_cast<double>(nx - 1) *
                      static_cast<double>(nx);
    const double ly = t.ly / static_cast<double>(t.ny) * static_cast<double>(t.ny - 1) / static_cast<double>(ny - 1) *
                      static_cast<double>(ny);
    t.h.swap(out);
    t.nx = nx;
    t.ny = ny;
    t.lx = lx;
    t.ly = ly;
}

RadialPsd radial_psd(const Topography &t, int32_t window, int64_t nbins) {
    if (nbins < 1 || nbins > 1000000) fail(GFMD_ERR_INVALID_ARG, "nbins must be in 1..1e6");
    if (t.nx * t.ny < 2) fail(GFMD_ERR_STATE, "a single point has no spectrum");
    const Spectrum s = transform(t, window, false);
    double qmin = std::numeric_limits<double>::infinity(), qmax = 0.0;
    for_each_mode(t, s, [&](double, double q2, double) {
        qmin = std::min(qmin, std::sqrt(q2));
        qmax = std::max(qmax, std::sqrt(q2));
    });
    RadialPsd out;
    out.q.assign(static_cast<std::size_t>(nbins), 0.0);
    out.c.assign(static_cast<std::size_t>(nbins), 0.0);
    out.count.assign(static_cast<std::size_t>(nbins), 0);
    const double span = std::log(qmax / qmin);
    for_each_mode(t, s, [&](double w, double q2, double a2) {
        const double q = std::sqrt(q2);
        const double at = span > 0.0 ? static_cast<double>(nbins) * std::log(q / qmin) / span : 0.0;
        const int64_t k = at >= 0.0 ? std::min(static_cast<int64_t>(at), nbins - 1) : 0;
        out.q[static_cast<std::size_t>(k)] += w * q;
        out.c[static_cast<std::size_t>(k)] += w * a2;
        out.count[static_cast<std::size_t>(k)] += static_cast<int64_t>(w);
    });
    const double area = t.lx / (2.0 * kPi) * s.scale * (t.ly / (2.0 * kPi)) * s.scale;
    for (int64_t k = 0; k < nbins; ++k) {
        const auto i = static_cast<std::size_t>(k);
        if (out.count[i] > 0) {
            out.q[i] /= static_cast<double>(out.count[i]);
            out.c[i] *= area / static_cast<double>(out.count[i]);
            if (!std::isfinite(out.c[i])) fail(GFMD_ERR_RANGE, "the PSD overflows double precision");
        } else {  // an empty bin: its centre, C = 0
            out.q[i] = qmin * std::exp(span * (static_cast<double>(k) + 0.5) / static_cast<double>(nbins));
        }
    }
    return out;
}

RadialPsd profile_psd(const Topography &t, int32_t window) {
    if (t.nx < 2) fail(GFMD_ERR_STATE, "profiles of one point have no spectrum");
    const Spectrum s = transform(t, window, true);
    RadialPsd out;
    const auto m = static_cast<std::size_t>(s.nxh);
    out.q.resize(m);
    out.c.assign(m, 0.0);
    out.count.resize(m);
    for (int64_t ky = 0; ky < t.ny; ++ky)
        for (std::size_t k = 0; k < m; ++k) out.c[k] += std::norm(s.hq[static_cast<std::size_t>(ky) * m + k]);
    for (std::size_t k = 0; k < m; ++k) {
        out.q[k] = 2.0 * kPi * static_cast<double>(k) / t.lx;
        out.c[k] *= t.lx / (2.0 * kPi) * s.scale / static_cast<double>(t.ny) * s.scale;
        if (!std::isfinite(out.c[k])) fail(GFMD_ERR_RANGE, "the PSD overflows double precision");
        out.count[k] = (k == 0 || (t.nx % 2 == 0 && static_cast<int64_t>(k) == t.nx / 2)) ? 1 : 2;
    }
    return out;
}

SpectralMoments spectral_moments(const Topography &t, int32_t window) {
    const Spectrum s = transform(t, window, false);
    double m0 = 0.0, m2 = 0.0, m4 = 0.0;
    for_each_mode(t, s, [&](double w, double q2, double a2) {
        m0 += w * a2;
        m2 += w * q2 * a2;
        m4 += w * q2 * q2 * a2;
    });
    const SpectralMoments m{std::sqrt(m0) * s.scale, std::sqrt(m2) * s.scale, 0.5 * std::sqrt(m4) * s.scale};
    if (!(std::isfinite(m.rms_height) && std::isfinite(m.rms_slope) && std::isfinite(m.rms_curvature)))
        fail(GFMD_ERR_RANGE, "the spectrum's moments overflow double precision");
    return m;
}

namespace {
void check_body(int32_t kind, double width, double nu, double e_star) {
    validate_green_kind(kind);
    if (kind != GFMD_GREEN_HALFSPACE && !(std::isfinite(width) && width > 0.0))
        fail(GFMD_ERR_INVALID_ARG, "a layer's width must be finite and > 0");
    if (kind == GFMD_GREEN_LAYER_BONDED) validate_poisson(nu);
    if (!(std::isfinite(e_star) && e_star > 0.0)) fail(GFMD_ERR_INVALID_ARG, "e_star must be finite and > 0");
}

// The stiffness 1/G(q) = q E* / (2 f(q w)) of the body at |q|
double body_stiffness(int32_t kind, double width, double nu, double e_star, double q) {
    const double f = kind == GFMD_GREEN_HALFSPACE ? 1.0 : green_factor(kind, q * width, nu);
    return q * e_star / (2.0 * f);
}
}  // namespace

double topography_persson_variance(const Topography &t, int32_t window, int32_t kind, double width, double nu,
                                   double e_star) {
    check_body(kind, width, nu, e_star);
    const Spectrum s = transform(t, window, false);
    double v = 0.0;
    for_each_mode(t, s, [&](double w, double q2, double a2) {
        const double k = body_stiffness(kind, width, nu, e_star, std::sqrt(q2)) * s.scale;  // times the scale
        v += w * k * k * a2;
    });
    if (!std::isfinite(v)) fail(GFMD_ERR_RANGE, "the full-contact pressure variance overflows double precision");
    return v;
}


// Persson's mean gap.  The elastic energy of the contact at load p is
//   U(p) / A0 = (1/2) sum_q |h_q|^2 k(q) W(q, p),  W = P [gamma + (1 - gamma) P^2],
// P(q, p) = erf(p / sqrt(2 V(q))) the contact area seen at magnification q, V(q) the full-contact
// pressure variance of the modes up to |q| (V = 2 G(q) of Persson's notation: on a half-space
// k = q E*/2 and this is the theory of Yang & Persson's Eq. 2, its integrals the grid's sums), and
// the mean gap follows from p = -dU/du / A0 with u(infinity) = 0:
//   u(p) = int_p^inf dp'/p' dU/dp' / A0 = sum_q |h_q|^2 k(q) / (2 sqrt(2 V(q))) J(p / sqrt(2 V(q))),
//   J(s0) = (2/sqrt(pi)) int_s0^inf ds/s [gamma + 3 (1 - gamma) erf(s)^2] e^(-s^2)
//         = (gamma/sqrt(pi)) E1(s0^2) + (6 (1 - gamma)/sqrt(pi)) K(s0),
//   K(s0) = int_s0^inf erf(s)^2 e^(-s^2) ds / s,
// after s = p'/sqrt(2 V(q)).  K is smooth and bounded (erf^2/s ~ 4 s/pi at 0): tabulated once on
// [0, 8] (K(8) ~ 1e-30) by Simpson's rule from the top and interpolated by cubic Hermite with its
// exact derivative, to ~1e-13.
namespace {

constexpr double kTableEnd = 8.0;
constexpr int kTableSteps = 8192;

double k_derivative(double s) {
    if (s == 0.0) return 0.0;
    const double e = std::erf(s);
    return -e * e * std::exp(-s * s) / s;
}

const std::vector<double> &k_table() {
    static const std::vector<double> table = [] {
        std::vector<double> k(kTableSteps + 1, 0.0);
        const double h = kTableEnd / kTableSteps;
        for (int i = kTableSteps - 1; i >= 0; --i) {  // Simpson on [s_i, s_i+1] with its midpoint
            const double a = i * h;
            k[static_cast<std::size_t>(i)] = k[static_cast<std::size_t>(i) + 1] -
                h / 6.0 * (k_derivative(a) + 4.0 * k_derivative(a + 0.5 * h) + k_derivative(a + h));
        }
        return k;
    }();
    return table;
}

double k_integral(double s) {
    if (!(s < kTableEnd)) return 0.0;
    const std::vector<double> &k = k_table();
    const double h = kTableEnd / kTableSteps, x = s / h;
    const auto i = std::min(static_cast<int>(x), kTableSteps - 1);
    const double u = x - i, a = i * h;
    const double h00 = (1 + 2 * u) * (1 - u) * (1 - u), h10 = u * (1 - u) * (1 - u), h01 = u * u * (3 - 2 * u),
                 h11 = u * u * (u - 1);
    return h00 * k[static_cast<std::size_t>(i)] + h10 * h * k_derivative(a) + h01 * k[static_cast<std::size_t>(i) + 1] +
           h11 * h * k_derivative(a + h);
}

double gap_kernel(double s0, double gamma) {
    const double x = s0 * s0;
    const double e1 = x > 700.0 ? 0.0 : -std::expint(-x);  // E1(x) = -Ei(-x)
    return (gamma * e1 + 6.0 * (1.0 - gamma) * k_integral(s0)) / std::sqrt(kPi);
}

}  // namespace

double topography_persson_mean_gap(const Topography &t, int32_t window, int32_t kind, double width, double nu,
                                   double e_star, double sigma0, double gamma) {
    check_body(kind, width, nu, e_star);
    if (!(std::isfinite(sigma0) && sigma0 > 0.0))
        fail(GFMD_ERR_INVALID_ARG, "sigma0 must be finite and > 0 (the mean gap diverges at zero load)");
    if (!(gamma >= 0.0 && gamma <= 1.0)) fail(GFMD_ERR_INVALID_ARG, "gamma must be in [0, 1]");
    const Spectrum s = transform(t, window, false);
    struct Mode {
        double q2, variance, energy;  // |q|^2; w |h_q|^2 k^2 and w |h_q|^2 k / 2, over scale^2
    };
    std::vector<Mode> modes;
    modes.reserve(static_cast<std::size_t>(t.ny) * static_cast<std::size_t>(s.nxh));
    for_each_mode(t, s, [&](double w, double q2, double a2) {
        const double k = body_stiffness(kind, width, nu, e_star, std::sqrt(q2));
        modes.push_back({q2, w * a2 * k * k, 0.5 * w * a2 * k});
    });
    std::sort(modes.begin(), modes.end(), [](const Mode &a, const Mode &b) { return a.q2 < b.q2; });
    // sigma0 / scale against sqrt(2 V / scale^2); the sum (|h|^2 / sqrt(V)) times scale at the end
    const double p = sigma0 / s.scale;
    double v = 0.0, gap = 0.0;
    for (std::size_t i = 0; i < modes.size();) {
        std::size_t j = i;  // the modes of one |q|: V(q) holds them all
        while (j < modes.size() && modes[j].q2 == modes[i].q2) v += modes[j++].variance;
        if (v > 0.0) {
            const double root = std::sqrt(2.0 * v), kernel = gap_kernel(p / root, gamma) / root;
            for (; i < j; ++i) gap += modes[i].energy * kernel;
        }
        i = j;
    }
    gap *= s.scale;
    if (!std::isfinite(gap) || !std::isfinite(v)) fail(GFMD_ERR_RANGE, "Persson's mean gap overflows double precision");
    return gap;
}

}  // namespace gfmd

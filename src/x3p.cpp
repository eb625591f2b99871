#include "x3p.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>

#include "error.hpp"
#include "gfmd.h"

#ifdef GFMD_HAVE_X3P
#include <libxml/parser.h>
#include <libxml/tree.h>
#include <zip.h>
#endif

namespace gfmd {

bool looks_like_zip(const std::string &bytes) { return bytes.compare(0, 4, std::string("PK\x03\x04", 4)) == 0; }

#ifndef GFMD_HAVE_X3P

bool x3p_supported() { return false; }

Topography from_x3p(const std::string &, double) {
    fail(GFMD_ERR_STATE, "this build of gfmd reads no x3p files: it was configured without libzip and libxml2 "
                         "(Debian: apt-get install libzip-dev libxml2-dev, then configure and build again)");
}

#else

namespace {

[[noreturn]] void bad(const std::string &what) { fail(GFMD_ERR_FORMAT, "x3p: " + what); }

// The limits of what is read before the grid is known: main.xml (a few kB in practice).
constexpr zip_uint64_t kMaxXml = 16u << 20;

struct ZipCloser {
    void operator()(zip_t *z) const { zip_discard(z); }
};
struct XmlFree {
    void operator()(xmlDoc *d) const { xmlFreeDoc(d); }
};

// An archive member's bytes, its declared size checked against `limit` before allocation and
// the bytes read against the declaration.
std::string member(zip_t *z, const std::string &name, zip_uint64_t limit) {
    zip_stat_t st;
    zip_stat_init(&st);
    if (zip_stat(z, name.c_str(), 0, &st) != 0 || !(st.valid & ZIP_STAT_SIZE))
        bad("the archive has no member '" + name + "'");
    if (st.size > limit)
        bad("member '" + name + "' declares " + std::to_string(st.size) + " bytes, more than the " +
            std::to_string(limit) + " its header implies");
    std::unique_ptr<zip_file_t, int (*)(zip_file_t *)> f(zip_fopen(z, name.c_str(), 0), zip_fclose);
    if (!f) bad("member '" + name + "' cannot be opened: " + zip_strerror(z));
    std::string out(static_cast<std::size_t>(st.size), '\0');
    zip_uint64_t got = 0;
    while (got < st.size) {
        const zip_int64_t n = zip_fread(f.get(), out.data() + got, st.size - got);
        if (n <= 0) bad("member '" + name + "' is truncated or corrupted after byte " + std::to_string(got));
        got += static_cast<zip_uint64_t>(n);
    }
    char extra = 0;
    if (zip_fread(f.get(), &extra, 1) > 0) bad("member '" + name + "' is longer than it declares");
    return out;
}

// The first element of this local name (namespaces ignored) below `node`, depth first.
xmlNode *find(xmlNode *node, const char *name) {
    for (xmlNode *n = node; n != nullptr; n = n->next) {
        if (n->type != XML_ELEMENT_NODE) continue;
        if (std::strcmp(reinterpret_cast<const char *>(n->name), name) == 0) return n;
        if (xmlNode *c = find(n->children, name)) return c;
    }
    return nullptr;
}

std::string text(xmlNode *n) {
    xmlChar *c = xmlNodeGetContent(n);
    std::string s = c ? reinterpret_cast<const char *>(c) : "";
    xmlFree(c);
    const auto b = s.find_first_not_of(" \t\r\n"), e = s.find_last_not_of(" \t\r\n");
    return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

std::string child_text(xmlNode *parent, const char *name, const char *where, bool required = true) {
    xmlNode *n = parent ? find(parent->children, name) : nullptr;
    if (n == nullptr) {
        if (required) bad(std::string("main.xml has no ") + where + "/" + name);
        return {};
    }
    return text(n);
}

double number(const std::string &s, const std::string &what) {
    char *end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (s.empty() || end == nullptr || *end != '\0' || !std::isfinite(v)) bad(what + " is not a finite number: '" + s + "'");
    return v;
}

int64_t count(const std::string &s, const std::string &what) {
    const double v = number(s, what);
    if (!(v >= 1.0 && v <= 2147483648.0) || v != std::floor(v)) bad(what + " must be a whole number >= 1, got '" + s + "'");
    return static_cast<int64_t>(v);
}

struct Axis {
    char type = 'I', data = 'D';
    double increment = 1.0, offset = 0.0;
};

Axis axis(xmlNode *axes, const char *name) {
    xmlNode *a = axes ? find(axes->children, name) : nullptr;
    if (a == nullptr) bad(std::string("main.xml has no Record1/Axes/") + name);
    Axis out;
    const std::string where = std::string("Record1/Axes/") + name;
    const std::string type = child_text(a, "AxisType", where.c_str());
    if (type != "I" && type != "A") bad(where + "/AxisType must be I or A, got '" + type + "'");
    out.type = type[0];
    const std::string data = child_text(a, "DataType", where.c_str(), false);
    if (!data.empty()) {
        if (data.size() != 1 || std::strchr("ILFD", data[0]) == nullptr)
            bad(where + "/DataType must be I, L, F or D, got '" + data + "'");
        out.data = data[0];
    }
    const std::string inc = child_text(a, "Increment", where.c_str(), false);
    if (!inc.empty()) out.increment = number(inc, where + "/Increment");
    const std::string off = child_text(a, "Offset", where.c_str(), false);
    if (!off.empty()) out.offset = number(off, where + "/Offset");
    return out;
}

int bytes_of(char type) { return type == 'I' ? 2 : (type == 'L' || type == 'F') ? 4 : 8; }

// Value i of little-endian data of this type (x3p's binary is little-endian), as a double.
double value(const unsigned char *p, char type) {
    uint64_t u = 0;
    const int n = bytes_of(type);
    for (int k = 0; k < n; ++k) u |= static_cast<uint64_t>(p[k]) << (8 * k);
    switch (type) {
    case 'I': return static_cast<double>(static_cast<int16_t>(u));
    case 'L': return static_cast<double>(static_cast<int32_t>(u));
    case 'F': {
        float f;
        const auto v = static_cast<uint32_t>(u);
        std::memcpy(&f, &v, 4);
        return static_cast<double>(f);
    }
    default: {
        double d;
        std::memcpy(&d, &u, 8);
        return d;
    }
    }
}

}  // namespace

bool x3p_supported() { return true; }

Topography from_x3p(const std::string &bytes, double unit) {
    zip_error_t error;
    zip_error_init(&error);
    zip_source_t *src = zip_source_buffer_create(bytes.data(), bytes.size(), 0, &error);
    if (src == nullptr) bad(std::string("cannot read the archive: ") + zip_error_strerror(&error));
    std::unique_ptr<zip_t, ZipCloser> z(zip_open_from_source(src, ZIP_RDONLY, &error));
    if (!z) {
        zip_source_free(src);
        const std::string why = zip_error_strerror(&error);
        zip_error_fini(&error);
        bad("not a readable zip archive (" + why + ")");
    }
    zip_error_fini(&error);

    const std::string xml = member(z.get(), "main.xml", kMaxXml);
    // no network, no entity substitution (no external entities), no DTD loading
    std::unique_ptr<xmlDoc, XmlFree> doc(xmlReadMemory(xml.data(), static_cast<int>(xml.size()), "main.xml", nullptr,
                                                       XML_PARSE_NONET | XML_PARSE_NOERROR | XML_PARSE_NOWARNING));
    if (!doc) bad("main.xml is not well-formed XML");
    xmlNode *root = xmlDocGetRootElement(doc.get());
    if (root == nullptr || std::strcmp(reinterpret_cast<const char *>(root->name), "ISO5436_2") != 0)
        bad("main.xml's root element is not ISO5436_2");
    xmlNode *r1 = find(root->children, "Record1"), *r3 = find(root->children, "Record3");
    if (r1 == nullptr || r3 == nullptr) bad("main.xml has no Record1 or no Record3");
    const std::string feature = child_text(r1, "FeatureType", "Record1");
    if (feature != "SUR" && feature != "PRF")
        bad("FeatureType '" + feature + "': only surfaces (SUR) and profiles (PRF) are grids of heights");
    xmlNode *axes = find(r1->children, "Axes");
    const Axis cx = axis(axes, "CX"), cy = axis(axes, "CY"), cz = axis(axes, "CZ");
    if (cx.type != 'I' || cy.type != 'I')
        bad("absolute x or y axes (AxisType A: a point cloud) are not a grid; only incremental axes are read");
    if (!(cx.increment > 0.0) || !(cy.increment > 0.0)) bad("the x and y increments must be > 0");
    xmlNode *dims = find(r3->children, "MatrixDimension");
    if (dims == nullptr) bad("main.xml has no Record3/MatrixDimension");
    const int64_t nx = count(child_text(dims, "SizeX", "Record3/MatrixDimension"), "SizeX");
    const int64_t ny = count(child_text(dims, "SizeY", "Record3/MatrixDimension"), "SizeY");
    const int64_t nz = count(child_text(dims, "SizeZ", "Record3/MatrixDimension"), "SizeZ");
    if (nz != 1) bad("SizeZ = " + std::to_string(nz) + ": only single layers (SizeZ = 1) are surfaces");
    if (nx > (int64_t{1} << 40) / ny) bad("a grid of " + std::to_string(nx) + " x " + std::to_string(ny) + " points");
    const auto points = static_cast<zip_uint64_t>(nx * ny);
    const int size = bytes_of(cz.data);

    Topography out;
    out.nx = nx;
    out.ny = ny;
    out.format = GFMD_TOPO_X3P;
    out.has_units = true;  // the standard's unit is the metre
    out.lx = static_cast<double>(nx) * cx.increment / unit;
    out.ly = static_cast<double>(ny) * cy.increment / unit;
    xmlNode *link = find(r3->children, "DataLink");
    if (link != nullptr) {
        const std::string path = child_text(link, "PointDataLink", "Record3/DataLink");
        const std::string data = member(z.get(), path, points * static_cast<zip_uint64_t>(size));
        if (data.size() != points * static_cast<zip_uint64_t>(size))
            bad("'" + path + "' holds " + std::to_string(data.size()) + " bytes; " + std::to_string(nx) + " x " +
                std::to_string(ny) + " values of type " + cz.data + " need " + std::to_string(points * size));
        out.h.resize(static_cast<std::size_t>(points));
        const auto *p = reinterpret_cast<const unsigned char *>(data.data());
        for (std::size_t i = 0; i < out.h.size(); ++i) out.h[i] = value(p + i * static_cast<std::size_t>(size), cz.data);
    } else {
        xmlNode *list = find(r3->children, "DataList");
        if (list == nullptr) bad("Record3 has neither a DataLink nor a DataList");
        out.h.reserve(static_cast<std::size_t>(points));
        for (xmlNode *d = list->children; d != nullptr; d = d->next) {
            if (d->type != XML_ELEMENT_NODE || std::strcmp(reinterpret_cast<const char *>(d->name), "Datum") != 0) continue;
            if (out.h.size() == points) bad("DataList holds more than SizeX x SizeY data");
            const std::string v = text(d);
            out.h.push_back(v.empty() ? std::numeric_limits<double>::quiet_NaN()  // an empty datum: invalid
                                      : number(v, "Datum " + std::to_string(out.h.size())));
        }
        if (out.h.size() != points)
            bad("DataList holds " + std::to_string(out.h.size()) + " data, SizeX x SizeY = " + std::to_string(points));
    }
    // the valid-points mask (one bit a point, least significant first; 0: invalid)
    const std::string valid_path = link ? child_text(link, "ValidPointsLink", "Record3/DataLink", false) : "";
    std::string valid;
    if (!valid_path.empty()) {
        valid = member(z.get(), valid_path, (points + 7) / 8);
        if (valid.size() != (points + 7) / 8) bad("'" + valid_path + "' does not hold one bit a point");
    }
    for (std::size_t i = 0; i < out.h.size(); ++i) {
        const bool masked = !valid.empty() && ((static_cast<unsigned char>(valid[i / 8]) >> (i % 8)) & 1u) == 0;
        if (masked || std::isnan(out.h[i])) {
            out.h[i] = std::numeric_limits<double>::quiet_NaN();
            continue;
        }
        if (std::isinf(out.h[i])) bad("the height at point " + std::to_string(i) + " is infinite");
        out.h[i] = (cz.offset + cz.increment * out.h[i]) / unit;
    }
    return out;
}

#endif

}  // namespace gfmd

// Internal error type: every failure inside the core is thrown as gfmd::Error and turned into a
// status plus message at the extern "C" boundary (c_api.cpp).
#ifndef GFMD_SRC_ERROR_HPP
#define GFMD_SRC_ERROR_HPP

#include <cstdint>
#include <stdexcept>
#include <string>

#include "gfmd.h"

namespace gfmd {

class Error : public std::runtime_error {
public:
    Error(int32_t status, const std::string &message) : std::runtime_error(message), status_(status) {}
    int32_t status() const noexcept { return status_; }

private:
    int32_t status_;
};

[[noreturn]] inline void fail(int32_t status, const std::string &message) { throw Error(status, message); }

}  // namespace gfmd

#endif

// The relaxation methods behind gfmd_step() and gfmd_relax(): one interface, one file per method.
// A solver moves z and v by one step from the forces of the last evaluation; the caller then
// re-evaluates the forces.  Its own adaptive state survives between calls (a relax in chunks
// follows the trajectory of one call) and is reset by restart() when the energy landscape or the
// dynamics change.
#ifndef GFMD_SRC_SOLVERS_SOLVER_HPP
#define GFMD_SRC_SOLVERS_SOLVER_HPP

#include <cstdint>
#include <memory>
#include <vector>

#include "../fft_grid.hpp"
#include "../fields.hpp"
#include "../forces.hpp"
#include "../green.hpp"
#include "../params.hpp"

namespace gfmd {

// A count kept in a solver's state (a vector of doubles): an exact integer in [0, 2^53].
inline bool valid_count(double x) {
    return x >= 0.0 && x <= 9007199254740992.0 && x == static_cast<double>(static_cast<int64_t>(x));
}

// The automatic (or user-set) dynamics of a body: dt = kDtFactor / omega_max (Verlet is stable up
// to 2/omega_max; 1 leaves room for the hard-wall collisions and the adhesive nonlinearity),
// damping eta = 2 kZeta omega_min: the slowest elastic mode slightly underdamped, every faster
// mode underdamped and decaying at the same rate eta/2.
constexpr double kDtFactor = 1.0;
constexpr double kZeta = 0.9;

struct Dynamics {
    double dt = 0.0, eta = 0.0;
};
Dynamics dynamics_for(const Params &p, const Body &body);

// Everything a step may read, and the fields it moves.
struct StepContext {
    const FftGrid &grid;
    const Params &params;
    const Body &body;
    const Dynamics &dynamics;
    const ForceState &forces;  // of the current z
    Fields &fields;
};

class Solver {
public:
    virtual ~Solver() = default;
    virtual void restart(const Dynamics &d) = 0;
    virtual void advance(StepContext &c) = 0;
    // Whether the caller should evaluate the forces and test convergence after this step.  A
    // solver whose steps do not read the forces (Polonsky & Keer's iteration moves the pressure)
    // may ask for the test only every few steps, on a schedule that depends on its own state
    // alone, so that a relax in chunks stops where one call does.  The default: every step.
    virtual bool at_check(const Params &) const { return true; }
    virtual std::unique_ptr<Solver> clone() const = 0;
    // The adaptive state as numbers, for checkpoints: state() and set_state() round-trip exactly;
    // set_state() throws GFMD_ERR_FORMAT for values the solver cannot have.
    virtual std::vector<double> state() const = 0;
    virtual void set_state(const std::vector<double> &s) = 0;
    // Grid-sized state beyond z and v that a checkpoint must keep (none for most solvers), and
    // its restoration after set_state(); throws GFMD_ERR_FORMAT for fields it cannot have.
    virtual std::vector<const RealBuffer *> grid_state() const { return {}; }
    virtual void set_grid_state(std::vector<RealBuffer> &&fields);
};

// A new, restarted solver of a kind (GFMD_SOLVER_*).  Throws GFMD_ERR_BAD_ENUM for an unknown kind,
// std::bad_alloc if its state does not fit.
std::unique_ptr<Solver> make_solver(int32_t kind, const FftGrid &grid, const Dynamics &d);

}  // namespace gfmd

#endif

#include "libsph/solid/quasi_static.hpp"

#include <algorithm>
#include <sstream>
#include <stdexcept>

#include "libsph/io/parameters.hpp"

namespace sph {

void declare_parameters(Parameters& p, RelaxationSettings& s) {
  p.add("residual_tolerance", s.tolerance, "-",
        "quasi-static convergence: |net force| <= tolerance |load| (l2 norms over the free particles)", {0, 1, true, false});
  p.add("residual_check_interval", s.check_interval, "-", "steps between residual checks", Range::closed(1, 1e6));
}

template <int Dim>
QuasiStaticRelaxation<Dim>::QuasiStaticRelaxation(ElasticSolid<Dim>& solid, RelaxationSettings settings)
    : solid_(solid), settings_(std::move(settings)) {
  const std::string body = "solid '" + solid_.particles().name() + "'";
  if (!(settings_.tolerance > 0)) throw std::invalid_argument(body + ": quasi-static residual tolerance must be positive");
  if (settings_.check_interval < 1) throw std::invalid_argument(body + ": quasi-static check interval must be >= 1");
  if (!(solid_.settings().damping_rate > 0)) throw std::invalid_argument(body + ": a quasi-static relaxation needs a damping rate > 0");
}

template <int Dim>
const typename QuasiStaticRelaxation<Dim>::Status& QuasiStaticRelaxation<Dim>::check(Real time) {
  const auto r = solid_.equilibrium_residual(time);
  status_.net = r.net;
  status_.load = std::max(r.load, r.active);
  status_.residual = status_.load > 0 ? status_.net / status_.load : std::numeric_limits<double>::infinity();
  status_.converged = status_.residual <= settings_.tolerance;
  return status_;
}

template <int Dim>
std::string QuasiStaticRelaxation<Dim>::not_converged(Real time) const {
  std::ostringstream s;
  s << "quasi-static solve of body '" << solid_.particles().name() << "' did not converge: residual " << status_.residual
    << " (net force " << status_.net << ", load " << status_.load << ") against the tolerance " << settings_.tolerance
    << " after " << status_.steps << " steps (pseudo-time " << time << ")";
  if (!(status_.load > 0)) s << "; the body carries no load to measure the residual against";
  return s.str();
}

template class QuasiStaticRelaxation<2>;
template class QuasiStaticRelaxation<3>;

}  // namespace sph

// The exact certifier snag-scan uses by default: decides the CCD queries the
// floating-point filter left uncertain with validate/exact_ccd.
#pragma once

#include <memory>

#include "libcd/pipeline/backend.hpp"

namespace snag::validate {

/// A Certifier backed by exact rational arithmetic (CGAL). `toi_width` is the
/// width to which the earliest time of impact is isolated (step units).
std::unique_ptr<Certifier> make_exact_certifier(double toi_width = 1e-9);

}  // namespace snag::validate

// SPDX-License-Identifier: LGPL-2.1-or-later
// Built without the designer (CAUSTICD_WITH_DESIGN off): the API answers
// that design is not built in, and finished designs already in the state
// directory still load as scenes.
#include "design_jobs.hpp"

namespace caustic::server {

DesignBackend design_backend() { return {nullptr, false}; }

}  // namespace caustic::server

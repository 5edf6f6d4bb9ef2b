// mwst/io/report.hpp — the JSON report of a run (what `mwst triangulate --json` writes).
#pragma once

#include <nlohmann/json.hpp>

#include "mwst/algorithms/pipeline.hpp"
#include "mwst/export.hpp"

namespace mwst {

// The keys: version, input, method, parameters, vertices, triangles, steiner, weight_total,
// weight_boundary, weight_interior, min_angle, max_angle, max_triangle_area, seconds (an object
// phase → seconds, plus "total"), stop_reason (refinement methods), duplicates, crossings,
// warnings, and one object per method-specific summary present in the Report (start, refine,
// conform, brh, flip, qtr, optimize; bundle_number, bundle_disk and bundle_circumdisk_bound).
MWST_API nlohmann::json to_json(const Report& report);

}  // namespace mwst

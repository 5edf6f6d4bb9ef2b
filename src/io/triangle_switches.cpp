// src/io/triangle_switches.cpp — parse_triangle_switches (mwst/io/triangle_switches.hpp): Triangle's
// switch string read one character at a time, numbers taken right after their switch.
#include "mwst/io/triangle_switches.hpp"

#include <charconv>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <system_error>

namespace mwst {

namespace {

[[noreturn]] void refuse(char letter, const std::string& why) {
  throw std::invalid_argument(std::string("-") + letter + ": " + why);
}

// The number right after a switch at `text[pos]`: digits with at most one '.'. Empty if none.
std::string_view number_after(std::string_view text, std::size_t pos) {
  std::size_t end = pos;
  while (end < text.size() && ((text[end] >= '0' && text[end] <= '9') || text[end] == '.')) ++end;
  return text.substr(pos, end - pos);
}

double decimal(char letter, std::string_view digits) {
  double value = 0.0;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (ec != std::errc() || end != digits.data() + digits.size()) {
    refuse(letter, "malformed number '" + std::string(digits) + "'");
  }
  return value;
}

std::size_t whole(char letter, std::string_view digits) {
  std::size_t value = 0;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (ec == std::errc::result_out_of_range) refuse(letter, "number '" + std::string(digits) + "' is too large");
  if (ec != std::errc() || end != digits.data() + digits.size()) {
    refuse(letter, "expected a whole number, found '" + std::string(digits) + "'");
  }
  return value;
}

// What parse_one collects beyond TriangleSwitches, settled once all arguments are read.
struct Pending {
  bool angle_given = false;     // q
  double angle = 20.0;          // q's number (Triangle's default 20°)
  unsigned no_bisect = 0;       // Y, once per Y
};

void parse_one(std::string_view text, TriangleSwitches& out, Pending& pending) {
  if (!text.empty() && text.front() == '-') text.remove_prefix(1);
  TriangulateOptions& o = out.options;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char letter = text[i];
    const std::string_view number = number_after(text, i + 1);
    bool takes_number = false;
    switch (letter) {
      case 'p': out.poly = true; break;
      case 'r': out.refine = true; break;
      case 'q':
        takes_number = true;
        out.quality = true;
        pending.angle_given = true;
        pending.angle = number.empty() ? 20.0 : decimal(letter, number);
        break;
      case 'a':
        takes_number = true;
        out.quality = true;
        if (number.empty()) {
          o.regional_area_limits = true;
        } else {
          o.max_area = decimal(letter, number);
          if (!(o.max_area > 0.0)) refuse(letter, "the maximum area must be greater than zero");
        }
        break;
      case 'A': out.region_attributes = true; break;
      case 'c': o.convex_hull = true; break;
      case 'D':
        o.conforming_delaunay = true;
        out.quality = true;
        break;
      case 'Y': ++pending.no_bisect; break;
      case 'S':
        takes_number = true;
        o.max_steiner = number.empty() ? 0 : whole(letter, number);
        break;
      case 'j': out.jettison = true; break;
      case 'e': out.edges = true; break;
      case 'v': out.voronoi = true; break;
      case 'n': out.neighbours = true; break;
      case 'z': out.zero_based = true; break;
      case 'B': out.no_boundary_markers = true; break;
      case 'P': out.no_poly_output = true; break;
      case 'N': out.no_node_output = true; break;
      case 'E': out.no_ele_output = true; break;
      case 'I': out.no_iteration_numbers = true; break;
      case 'O': out.ignore_holes = true; break;
      case 'Q': out.quiet = true; break;
      case 'V': ++out.verbosity; break;
      case 'h': out.help = true; break;
      // Triangle's own choices of algorithm and arithmetic: the mesh they ask for is the same.
      case 'i':
      case 'F':
      case 'l':
      case 's':
      case 'C':
      case 'X': out.ignored += letter; break;
      case 'u':
        refuse(letter, "user-defined size constraints (a compiled triunsuitable()) are not supported; "
                       "use -a with an area or the .poly's regional area limits");
      case 'g': refuse(letter, "Object File Format (.off) output is not supported");
      case 'o':
        if (i + 1 < text.size() && text[i + 1] == '2') {
          throw std::invalid_argument("-o2: second-order (six-node) triangles are not supported");
        }
        refuse(letter, "is no switch of Triangle's (did you mean -o2, which is not supported?)");
      default:
        if ((letter >= '0' && letter <= '9') || letter == '.') {
          const std::string stray(number_after(text, i));
          if (i == 0) throw std::invalid_argument("a number '" + stray + "' with no switch before it");
          refuse(text[i - 1], "takes no number, found '" + stray + "'");
        }
        throw std::invalid_argument(std::string("-") + letter + ": unknown switch (Triangle's switches are " +
                                    "prq_a_uAcDjevngBPNEIOXzo2YS_iFlsCQVh; mwst does all but u, g and o2)");
    }
    if (takes_number) i += number.size();
  }
}

}  // namespace

TriangleSwitches parse_triangle_switches(const std::vector<std::string>& arguments) {
  TriangleSwitches out;
  Pending pending;
  for (const std::string& argument : arguments) parse_one(argument, out, pending);
  TriangulateOptions& o = out.options;
  // Triangle's q alone bounds the angle; a and D alone refine with no angle bound.
  o.min_angle_deg = pending.angle_given ? pending.angle : 0.0;
  o.method = out.quality ? Method::kDr : Method::kDt;
  o.segment_splitting = pending.no_bisect == 0   ? SegmentSplitting::kAllowed
                        : pending.no_bisect == 1 ? SegmentSplitting::kNotBoundary
                                                 : SegmentSplitting::kNever;
  return out;
}

TriangleSwitches parse_triangle_switches(std::string_view switches) {
  return parse_triangle_switches(std::vector<std::string>{std::string(switches)});
}

}  // namespace mwst

// Figures 3 and 4 of Boyacı, Erten, Üngör, "Triangulations Loosing Bundles and Weight", as
// `mwst experiment figure3|figure4` makes them.
//
// Figure 3: the interior weight of Delaunay refinement (DT = 100) against the angle bound, 0°–20°
// in 1° steps, circumcenters against off-centers, for Ellipse and Florida (the paper's pair,
// figure3.png/.pdf), every data set on its own (figure3_NAME.png/.pdf) and all in one grid
// (figure3_all.png/.pdf). The numbers go to figure3.csv; the plots are drawn by gnuplot from a
// generated, self-contained script figure3.gp (the data are inlined as datablocks), so a reader can
// restyle them; without gnuplot the CSV and the script are still written and a warning says how to
// draw them later.
//
// Figure 4: per data set, the meshes of DT, QTR, DR, BRH, BRH+EFH and our optimiser side by side
// (figure4_NAME.png/.pdf; mwst/io/draw.hpp), input segments bold, Steiner points marked.
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

#include "experiments/experiment.hpp"
#include "support/parallel.hpp"

namespace mwst::experiments {

namespace {

// Figure 3's runs of one data set: normalised weight per (angle, rule), NaN when NA.
struct Curve {
  std::vector<double> angles;
  std::vector<double> circumcenter;
  std::vector<double> offcenter;
};

Curve curve_of(const Study& s, std::size_t d) {
  Curve c;
  c.angles = s.grids.figure3_angles;
  c.circumcenter.assign(c.angles.size(), std::nan(""));
  c.offcenter.assign(c.angles.size(), std::nan(""));
  for (std::size_t i = 0; i < s.sweep_specs.size(); ++i) {
    const RunSpec& spec = s.sweep_specs[i];
    if (spec.data_set != d || spec.options.method != Method::kDr) continue;
    const auto it = std::find(c.angles.begin(), c.angles.end(), spec.options.min_angle_deg);
    if (it == c.angles.end()) continue;
    const std::optional<double> v = normalised(s, d, s.sweep[i]);
    if (!v) continue;
    const auto k = static_cast<std::size_t>(it - c.angles.begin());
    (spec.options.steiner == SteinerRule::kOffCenter ? c.offcenter : c.circumcenter)[k] = *v;
  }
  return c;
}

std::string gp_number(double v) { return std::isnan(v) ? "?" : fixed(v, 4); }

// A gnuplot string literal (double quotes; backslashes and quotes escaped).
std::string gp_string(const std::string& s) {
  std::string q = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') q += '\\';
    q += c;
  }
  return q + "\"";
}

// The plot command of one data set's panel.
std::string panel(const std::string& block, const std::string& title) {
  std::ostringstream p;
  p << "set title " << gp_string(title) << "\n"
    << "plot " << block << " using 1:2 with linespoints ls 1 title \"circumcenters\", \\\n"
    << "     " << block << " using 1:3 with linespoints ls 2 title \"off-centers\", \\\n"
    << "     100 with lines ls 3 title \"DT\"\n";
  return p.str();
}

// figure3.csv: one row per DR run of the sweep (data set, angle bound, Steiner rule).
std::string figure3_csv(const Study& s) {
  const std::size_t n = s.data_sets.size();
  std::ostringstream csv;
  csv << "name,angle,rule,weight,steiner,min_angle,stop_reason\n";
  for (std::size_t d = 0; d < n; ++d) {
    for (const SteinerRule rule : {SteinerRule::kCircumcenter, SteinerRule::kOffCenter}) {
      for (const double a : s.grids.figure3_angles) {
        for (std::size_t i = 0; i < s.sweep_specs.size(); ++i) {
          const RunSpec& spec = s.sweep_specs[i];
          if (spec.data_set != d || spec.options.method != Method::kDr || spec.options.steiner != rule ||
              spec.options.min_angle_deg != a) {
            continue;
          }
          const RunResult& r = s.sweep[i];
          const std::optional<double> v = normalised(s, d, r);
          csv << s.data_sets[d].name << ',' << angle_text(a) << ',' << steiner_rule_name(rule) << ','
              << (v ? fixed(*v, 3) : "NA") << ',' << (r.ok ? std::to_string(r.report.steiner) : "NA") << ','
              << (r.ok ? fixed(r.report.min_angle, 3) : "NA") << ',' << (r.ok ? r.report.stop_reason : r.reason)
              << '\n';
        }
      }
    }
  }

  return csv.str();
}

// figure3.gp, its head and data: one inlined block of (angle, circumcenters, off-centers) per data
// set; `blocks` gets their names.
void write_gnuplot_data(const Study& s, std::ostringstream& gp, std::vector<std::string>& blocks) {
  const std::size_t n = s.data_sets.size();
  std::vector<Curve> curves;
  for (std::size_t d = 0; d < n; ++d) curves.push_back(curve_of(s, d));
  gp << "# figure3.gp: written by `mwst experiment figure3` (Figure 3 of Boyaci, Erten, Ungor,\n"
     << "# \"Triangulations Loosing Bundles and Weight\"): the interior weight of Delaunay refinement\n"
     << "# (DT = 100) against the angle bound, circumcenters against off-centers.\n"
     << "# Self-contained (the data are inlined below); run it in its own directory: gnuplot figure3.gp\n"
     << "# Writes figure3.png/.pdf (Ellipse and Florida), figure3_NAME.png/.pdf and figure3_all.png/.pdf.\n"
     << "set encoding utf8\nset datafile missing \"?\"\n\n";
  for (std::size_t d = 0; d < n; ++d) {
    const std::string block = "$data" + std::to_string(d);
    blocks.push_back(block);
    gp << "# " << s.data_sets[d].name << ": angle, circumcenters, off-centers\n" << block << " << EOD\n";
    const Curve& c = curves[d];
    for (std::size_t k = 0; k < c.angles.size(); ++k) {
      gp << angle_text(c.angles[k]) << ' ' << gp_number(c.circumcenter[k]) << ' ' << gp_number(c.offcenter[k]) << '\n';
    }
    gp << "EOD\n\n";
  }
}

// figure3.gp, its plots: the paper's pair (Ellipse and Florida), each data set alone, and all of
// them, each as PNG and PDF.
void write_gnuplot_plots(const Study& s, std::ostringstream& gp, const std::vector<std::string>& blocks) {
  const std::size_t n = s.data_sets.size();
  const double max_angle = s.grids.figure3_angles.empty() ? 20.0 : s.grids.figure3_angles.back();
  gp << "set style line 1 lc rgb \"#1f63b4\" lw 2 pt 7 ps 0.7\n"
     << "set style line 2 lc rgb \"#d62728\" lw 2 pt 5 ps 0.7\n"
     << "set style line 3 lc rgb \"#777777\" lw 1 dt 2\n"
     << "set xlabel \"angle bound (degrees)\"\n"
     << "set ylabel \"weight without boundary (DT = 100)\"\n"
     << "set xrange [0:" << angle_text(max_angle) << "]\nset xtics 2\nset grid\nset key outside right top vertical Left reverse\n\n";

  // The paper's pair, those of them that are here.
  std::vector<std::size_t> pair;
  for (const char* name : {"Ellipse", "Florida"}) {
    for (std::size_t d = 0; d < n; ++d) {
      if (s.data_sets[d].name == name) pair.push_back(d);
    }
  }
  struct Output {
    std::string stem;
    std::vector<std::size_t> panels;
    std::size_t columns;
    std::string title;
  };
  std::vector<Output> outputs;
  if (!pair.empty()) outputs.push_back({"figure3", pair, pair.size(), "Delaunay refinement: weight against the angle bound"});
  for (std::size_t d = 0; d < n; ++d) outputs.push_back({"figure3_" + s.data_sets[d].name, {d}, 1, ""});
  if (n > 1) {
    std::vector<std::size_t> all(n);
    for (std::size_t d = 0; d < n; ++d) all[d] = d;
    outputs.push_back({"figure3_all", all, std::min<std::size_t>(4, n), "Delaunay refinement: weight against the angle bound, all data sets"});
  }
  for (const Output& o : outputs) {
    const std::size_t rows = (o.panels.size() + o.columns - 1) / o.columns;
    const bool grid = o.panels.size() > 2;
    for (const bool pdf : {false, true}) {
      if (pdf) {
        gp << "set terminal pdfcairo noenhanced color font \"DejaVu Sans," << (grid ? 7 : 10) << "\" size "
           << fixed(static_cast<double>(o.columns) * (grid ? 3.2 : 5.0), 1) << "in,"
           << fixed(static_cast<double>(rows) * (grid ? 2.4 : 3.6) + (o.title.empty() ? 0.0 : 0.3), 1) << "in\n";
      } else {
        gp << "set terminal pngcairo noenhanced color font \"DejaVu Sans," << (grid ? 9 : 11) << "\" size "
           << o.columns * (grid ? 480 : 720) << ',' << rows * (grid ? 360 : 520) + (o.title.empty() ? 0 : 30) << "\n";
      }
      gp << "set output \"" << o.stem << (pdf ? ".pdf" : ".png") << "\"\n";
      if (o.panels.size() > 1 || !o.title.empty()) {
        gp << "set multiplot layout " << rows << ',' << o.columns;
        if (!o.title.empty()) gp << " title " << gp_string(o.title);
        gp << '\n';
      }
      for (const std::size_t d : o.panels) gp << panel(blocks[d], s.data_sets[d].name);
      if (o.panels.size() > 1 || !o.title.empty()) gp << "unset multiplot\n";
      gp << "set output\n\n";
    }
  }
}

}  // namespace

std::vector<OutputFile> figure3_files(const Study& s) {
  std::ostringstream gp;
  std::vector<std::string> blocks;
  write_gnuplot_data(s, gp, blocks);
  write_gnuplot_plots(s, gp, blocks);
  return {{"figure3.csv", figure3_csv(s)}, {"figure3.gp", gp.str()}};
}

std::string run_gnuplot(const std::string& out_dir, const std::string& script) {
  const std::string log = out_dir + "/gnuplot.log";
  const std::string how = "; the data are in " + out_dir + "/figure3.csv and the plots can be made later with: cd " +
                          out_dir + " && gnuplot " + script + " (Debian: apt-get install gnuplot-nox)";
  const pid_t pid = ::fork();
  if (pid < 0) return std::string("cannot start gnuplot: ") + std::strerror(errno) + how;
  if (pid == 0) {
    // Child: only async-signal-safe calls until exec.
    if (::chdir(out_dir.c_str()) != 0) ::_exit(126);
    const int fd = ::open("gnuplot.log", O_WRONLY | O_CREAT | O_TRUNC, 0666);
    if (fd >= 0) {
      ::dup2(fd, STDERR_FILENO);
      ::dup2(fd, STDOUT_FILENO);
      ::close(fd);
    }
    const int null_in = ::open("/dev/null", O_RDONLY);
    if (null_in >= 0) ::dup2(null_in, STDIN_FILENO);
    ::execlp("gnuplot", "gnuplot", script.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return std::string("waiting for gnuplot: ") + std::strerror(errno) + how;
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
    // gnuplot prints warnings on stderr even when it succeeds; keep the log only if it has any.
    std::ifstream in(log);
    std::string first;
    std::getline(in, first);
    if (first.empty()) ::unlink(log.c_str());
    return {};
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 127) {
    ::unlink(log.c_str());
    return "gnuplot not found: Figure 3's plots were not drawn" + how;
  }
  std::ifstream in(log);
  std::string first;
  std::getline(in, first);
  return "gnuplot failed (" + log + ": " + first + ")" + how;
}

std::vector<OutputFile> figure4_files(const Study& s, std::size_t workers, Progress& progress) {
  const std::size_t n = s.data_sets.size();
  std::vector<OutputFile> files(2 * n);
  progress.line("figure 4: drawing " + std::to_string(n) + " data sets");
  support::parallel_for(2 * n, workers, [&](std::size_t job) {
    const std::size_t d = job / 2;
    const bool pdf = job % 2 == 1;
    const DataSet& ds = s.data_sets[d];
    std::vector<io::Picture> panels;
    for (const Column c : kColumns) {
      const std::size_t ci = static_cast<std::size_t>(c);
      // The final run of this column, if one was planned.
      const RunResult* r_ptr = nullptr;
      const TriangulateOptions* o_ptr = nullptr;
      if (!s.final_index.empty() && s.final_index[d][ci].has_value()) {
        r_ptr = &s.finals[s.final_index[d][ci].value()];
        o_ptr = &s.final_specs[s.final_index[d][ci].value()].options;
      }
      io::Picture pic;
      std::string title = column_name(c);
      if (r_ptr && r_ptr->ok && r_ptr->picture) {
        const RunResult& r = *r_ptr;
        const TriangulateOptions& o = *o_ptr;
        pic = *r.picture;
        if (o.method == Method::kDr) {
          title += " (" + angle_text(o.min_angle_deg) + "°, " +
                   (o.steiner == SteinerRule::kOffCenter ? "off-centers" : "circumcenters") + ")";
        } else if (o.method == Method::kBrh) {
          title += " (" + angle_text(o.min_angle_deg) + "°, K = " +
                   std::to_string(o.bundle_k != 0 ? o.bundle_k : default_bundle_k(o.min_angle_deg)) + ")";
        }
        const std::optional<double> v = normalised(s, d, r);
        title += ": " + (v ? fixed(*v, 1) : std::string("NA")) + ", " + std::to_string(r.report.steiner) + " Steiner";
        if (r.report.bundle) {
          title += ", bundle " + std::to_string(r.report.bundle->bundle_number);
        }
      } else {
        std::string reason = "not run";
        if (!s.choices.empty() && !s.choices[d][ci].reason.empty()) reason = s.choices[d][ci].reason;
        if (r_ptr && !r_ptr->ok) reason = r_ptr->reason;
        pic.note = "NA: " + reason;
      }
      pic.title = title;
      panels.push_back(std::move(pic));
    }
    io::DrawOptions options;
    options.columns = 3;
    options.panel_size = 520.0;
    options.caption = ds.name + ": " + std::to_string(ds.pslg.points.size()) + " points, " +
                      std::to_string(ds.pslg.segments.size()) +
                      " segments. Weight without boundary, DT = 100; bold: input segments and boundary; "
                      "red: Steiner points";
    OutputFile& out = files[job];
    out.name = "figure4_" + ds.name + (pdf ? ".pdf" : ".png");
    try {
      out.content = io::render_pictures(panels, pdf ? io::PictureFormat::kPdf : io::PictureFormat::kPng, options);
    } catch (const std::exception& e) {
      out.content.clear();
      out.name += ".failed";
      out.content = e.what();
    }
  });
  std::vector<OutputFile> ok;
  for (OutputFile& f : files) {
    if (f.name.size() > 7 && f.name.ends_with(".failed")) {
      progress.line("figure 4: drawing " + f.name.substr(0, f.name.size() - 7) + " failed: " + f.content);
      continue;
    }
    ok.push_back(std::move(f));
  }
  return ok;
}

}  // namespace mwst::experiments

#include "app/plot.h"

#include <sys/wait.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>

#include "app/commands.h"
#include "app/result_reader.h"

namespace momenta {

namespace {

/// `text` as a gnuplot single-quoted string (a quote is doubled).
std::string Quoted(const std::string& text) {
  std::string q = "'";
  for (char c : text) q += c == '\'' ? std::string("''") : std::string(1, c);
  return q + "'";
}

bool EndsWith(const std::string& s, const std::string& tail) {
  if (s.size() < tail.size()) return false;
  for (size_t k = 0; k < tail.size(); ++k) {
    if (std::tolower(static_cast<unsigned char>(s[s.size() - tail.size() + k])) != tail[k])
      return false;
  }
  return true;
}

/// The columns asked for: -y may be given several times and each may hold a comma-separated list.
std::vector<std::string> Names(const std::vector<std::string>& specs) {
  std::vector<std::string> out;
  for (const auto& spec : specs) {
    std::stringstream s(spec);
    std::string name;
    while (std::getline(s, name, ',')) {
      if (!name.empty()) out.push_back(name);
    }
  }
  return out;
}

}  // namespace

std::string GnuplotScript(const PlotArgs& args, const std::string& out_path) {
  const ResultTable r = ReadResult(args.result);
  const std::vector<std::string> names = Names(args.columns);
  if (names.empty())
    throw std::invalid_argument("-y names no column (valid: " + JoinNames(r.names, 60) + ")");
  std::vector<size_t> cols;
  for (const auto& n : names) cols.push_back(r.Column(n));

  std::ostringstream g;
  g.precision(17);
  const bool png = EndsWith(out_path, ".png");
  g << "set terminal " << (png ? "pngcairo" : "svg dynamic") << " noenhanced size " << args.width
    << "," << args.width * 5 / 9 << " font 'sans,11'\n";
  g << "set output " << Quoted(out_path) << "\n";
  g << "set title " << Quoted(args.title.empty() ? args.result : args.title) << "\n";
  g << "set xlabel 'time [s]'\nset grid\nset key outside right top\n";
  // Events: two rows at one time.
  for (size_t i = 1; i < r.time.size(); ++i) {
    if (r.time[i] == r.time[i - 1] && (i < 2 || r.time[i - 2] != r.time[i])) {
      g << "set arrow from " << r.time[i] << ", graph 0 to " << r.time[i]
        << ", graph 1 nohead dashtype 2 linecolor rgb '#999999'\n";
    }
  }
  // The data inline, one block: time then the chosen columns.
  g << "$momenta << EOD\n";
  for (size_t i = 0; i < r.time.size(); ++i) {
    g << r.time[i];
    for (size_t c : cols) g << ' ' << r.values[c][i];
    g << '\n';
  }
  g << "EOD\nplot ";
  for (size_t k = 0; k < cols.size(); ++k) {
    g << (k ? ", " : "") << "$momenta using 1:" << k + 2 << " with lines linewidth 1.5 title "
      << Quoted(names[k]);
  }
  g << "\nunset output\n";
  return g.str();
}

int RunPlot(const PlotArgs& args) {
  const std::string out = args.out.empty() ? WithExtension(args.result, ".svg") : args.out;
  if (!EndsWith(out, ".svg") && !EndsWith(out, ".png")) {
    std::cerr << "momenta: -o " << out
              << ": the plot is written as SVG or PNG, chosen by the extension (.svg or .png)\n";
    return kExitUsage;
  }
  std::string script;
  try {
    script = GnuplotScript(args, out);
  } catch (const std::invalid_argument& e) {
    std::cerr << "momenta: " << e.what() << "\n";
    return kExitUsage;
  } catch (const std::runtime_error& e) {
    std::cerr << "momenta: " << e.what() << "\n";
    return kExitUsage;
  }
  // gnuplot reads the program on its standard input; its messages go to our standard error.
  const char* gnuplot = std::getenv("MOMENTA_GNUPLOT");
  const std::string command = gnuplot && *gnuplot ? gnuplot : "gnuplot";
  // A gnuplot that stops reading early must not kill momenta with SIGPIPE.
  std::signal(SIGPIPE, SIG_IGN);
  FILE* pipe = popen(command.c_str(), "w");
  if (!pipe) {
    std::cerr
        << "momenta: cannot start gnuplot (install Debian's gnuplot-nox; scripts/setup.sh does)\n";
    return kExitSolver;
  }
  const bool written = std::fwrite(script.data(), 1, script.size(), pipe) == script.size();
  const int status = pclose(pipe);
  if (!written || status == -1 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    if (WIFEXITED(status) && WEXITSTATUS(status) == 127) {
      std::cerr << "momenta: gnuplot was not found (install Debian's gnuplot-nox; scripts/setup.sh "
                   "does)\n";
    } else {
      std::cerr << "momenta: gnuplot failed writing " << out << "\n";
    }
    return kExitSolver;
  }
  return kExitOk;
}

}  // namespace momenta

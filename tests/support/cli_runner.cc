#include "tests/support/cli_runner.h"

#include <stdlib.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace momenta::testing {

namespace {

/// 'text' with every ' written as '\'' so the shell passes it through as one word.
std::string ShellQuote(const std::string& text) {
  std::string q = "'";
  for (char c : text) {
    if (c == '\'') {
      q += "'\\''";
    } else {
      q += c;
    }
  }
  return q + "'";
}

}  // namespace

TempDir::TempDir() {
  char templ[] = "/tmp/momenta_test_XXXXXX";
  if (!mkdtemp(templ)) throw std::runtime_error("mkdtemp failed");
  path_ = templ;
}

TempDir::~TempDir() {
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
}

std::string TempDir::Write(const std::string& name, const std::string& text) const {
  std::string p = File(name);
  std::ofstream out(p, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + p);
  return p;
}

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

CliResult RunMomenta(const std::vector<std::string>& args, const std::string& workdir) {
  TempDir capture;
  std::string command = "cd " + ShellQuote(workdir) + " && " + ShellQuote(MOMENTA_BINARY);
  for (const auto& a : args) command += " " + ShellQuote(a);
  command += " >" + ShellQuote(capture.File("stdout")) + " 2>" + ShellQuote(capture.File("stderr")) +
             " </dev/null";
  const int status = std::system(command.c_str());
  CliResult r;
  if (status != -1 && WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
  r.out = ReadText(capture.File("stdout"));
  r.err = ReadText(capture.File("stderr"));
  return r;
}

}  // namespace momenta::testing

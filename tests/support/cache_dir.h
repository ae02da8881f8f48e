#pragma once
// A private cache for the native code a test compiles: MOMENTA_CACHE_DIR points into a fresh
// temporary directory while the object lives, and both go with it.

#include <cstdlib>
#include <string>

#include "tests/support/cli_runner.h"

namespace momenta::testing {

class ScopedCacheDir {
 public:
  ScopedCacheDir() { ::setenv("MOMENTA_CACHE_DIR", dir_.path().c_str(), 1); }
  ~ScopedCacheDir() { ::unsetenv("MOMENTA_CACHE_DIR"); }
  ScopedCacheDir(const ScopedCacheDir&) = delete;
  ScopedCacheDir& operator=(const ScopedCacheDir&) = delete;

  const std::string& path() const { return dir_.path(); }

 private:
  TempDir dir_;
};

}  // namespace momenta::testing

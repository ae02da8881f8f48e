// The zip plugin (app/zip_plugin.h): the only code of momenta that links libzip.

#include "app/zip_plugin.h"

#include <zip.h>

#include <cstdio>

#include "app/plugin.h"

namespace {

using momenta::ZipEntry;

/// Adds one entry (its data kept alive by the caller until zip_close); false on failure.
bool Add(zip_t* zip, const ZipEntry& e) {
  zip_source_t* source =
      e.path != nullptr ? zip_source_file(zip, e.path, 0, -1) : zip_source_buffer(zip, e.data, e.size, 0);
  if (source == nullptr) return false;
  if (zip_file_add(zip, e.name, source, ZIP_FL_OVERWRITE | ZIP_FL_ENC_UTF_8) < 0) {
    zip_source_free(source);
    return false;
  }
  return true;
}

int Write(const char* path, const ZipEntry* entries, size_t count, char* why, size_t why_size) {
  int error = 0;
  zip_t* zip = zip_open(path, ZIP_CREATE | ZIP_TRUNCATE, &error);
  if (zip == nullptr) {
    zip_error_t e;
    zip_error_init_with_code(&e, error);
    std::snprintf(why, why_size, "%s", zip_error_strerror(&e));
    zip_error_fini(&e);
    return 1;
  }
  bool ok = true;
  for (size_t k = 0; k < count && ok; ++k) ok = Add(zip, entries[k]);
  if (!ok || zip_close(zip) < 0) {
    std::snprintf(why, why_size, "%s", zip_strerror(zip));
    zip_discard(zip);
    return 1;
  }
  return 0;
}

constexpr momenta::ZipPluginTable kTable = {momenta::kPluginAbi, Write};

}  // namespace

extern "C" __attribute__((visibility("default"))) const void* momenta_zip_plugin() {
  return &kTable;
}

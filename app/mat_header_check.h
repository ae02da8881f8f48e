#pragma once
/// The check of a MAT result file's matrix headers before libmatio reads it: libmatio allocates
/// what a header claims (2^30 rows in a 10 KB file: 32 GiB), so every matrix's sizes are first
/// walked and compared with the file's size here, from the header bytes alone.

#include <cstdint>
#include <string>

namespace momenta {

/// Walks the MAT v4 matrices of the open file `fd` (`size` bytes; `path` for messages), as momenta,
/// OpenModelica and Dymola write result files: each a 20-byte header (type, rows, columns,
/// imaginary flag, name length), the name, then the values. Throws std::runtime_error "PATH: not
/// a valid result file: ..." naming the matrix whose header does not fit the file (sizes beyond
/// what is left, an unknown type, a cut-off header) or saying that the file is MAT v5 or v7.3.
void CheckMatHeaders(int fd, uint64_t size, const std::string& path);

}  // namespace momenta

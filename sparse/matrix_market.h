#pragma once
// Matrix Market coordinate files (real, integer or pattern; symmetric or general).
#include <string>

#include "ldlpgs/sparse/csc.h"

namespace ldlpgs {

// Reads a square symmetric matrix. A general file is accepted only if it is symmetric, values
// included. Pattern files get the values CHOLMOD's reader gives them: off-diagonals -1, diagonal
// 1 + the number of off-diagonal entries in its row, which makes them symmetric positive
// definite. Unlike CHOLMOD 3.0 (SuiteSparse 5.12), which leaves a missing diagonal out, we add
// it, so that every pattern matrix is positive definite (no test matrix lacks one). Throws InputError ("FILE:LINE: problem") on anything
// else: missing file, bad header, array/complex format, truncated data, index out of range,
// non-finite value, a value not an integer in an integer file, duplicate entry, non-square or
// unsymmetric matrix; and on a binary file, a line over 1 MiB or over 64 MiB of comments, having
// read little more than that (a chunk at a time: /dev/zero fails at its first 64 KiB). Named
// pipes (bash's <(...)) read as files do.
SymmetricCsc read_matrix_market(const std::string& path);

// Writes the lower triangle as "coordinate real symmetric", values to full precision.
void write_matrix_market(const std::string& path, const SymmetricCsc& a);

}  // namespace ldlpgs

/* sym3.h - eigen-decomposition of symmetric 3x3 matrices (cyclic Jacobi rotations), one at a time or eight in AVX-512 lanes. */
#ifndef JETMESH_SYM3_H
#define JETMESH_SYM3_H

/* a = (a00, a01, a02, a11, a12, a22). Writes the eigenvalues in descending
 * order to val and the unit eigenvectors as the columns of vec (row-major:
 * vec[3 * row + k] is component row of the k-th vector, a rotation, det +1).
 * Deterministic: a fixed sequence of operations for a given input. */
void jm_sym3_eigen(const double a[6], double val[3], double vec[9]);
/* jm_sym3_eigen on a[i] into val[i], vec[i] for i < n, with the same bits
 * (eight at a time where the CPU has AVX-512). */
void jm_sym3_eigen_n(int n, const double (*a)[6], double (*val)[3], double (*vec)[9]);
#endif

/* sym3.c - eigen-decomposition of a symmetric 3x3 matrix (cyclic Jacobi rotations). */
#include "sym3.h"
#include <math.h>

void jm_sym3_eigen(const double a[6], double val[3], double vec[9])
{
    double m[3][3] = {{a[0], a[1], a[2]}, {a[1], a[3], a[4]}, {a[2], a[4], a[5]}};
    double v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    double scale = fabs(a[0]) + fabs(a[3]) + fabs(a[5]) + fabs(a[1]) + fabs(a[2]) + fabs(a[4]);
    /* cyclic sweeps over (0,1), (0,2), (1,2); converges quadratically: a
     * handful of sweeps reach double precision */
    for (int sweep = 0; sweep < 32; sweep++) {
        double off = fabs(m[0][1]) + fabs(m[0][2]) + fabs(m[1][2]);
        if (!(off > 1e-15 * scale)) break;
        for (int p = 0; p < 2; p++)
            for (int q = p + 1; q < 3; q++) {
                if (m[p][q] == 0.0) continue;
                /* the rotation that zeroes m[p][q] (Golub & Van Loan, sym.schur2) */
                double theta = (m[q][q] - m[p][p]) / (2.0 * m[p][q]);
                double t = (theta >= 0.0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
                double c = 1.0 / sqrt(t * t + 1.0), s = t * c;
                for (int k = 0; k < 3; k++) { /* m = m J */
                    double mkp = m[k][p], mkq = m[k][q];
                    m[k][p] = c * mkp - s * mkq;
                    m[k][q] = s * mkp + c * mkq;
                }
                for (int k = 0; k < 3; k++) { /* m = J^T m */
                    double mpk = m[p][k], mqk = m[q][k];
                    m[p][k] = c * mpk - s * mqk;
                    m[q][k] = s * mpk + c * mqk;
                }
                m[p][q] = m[q][p] = 0.0;
                for (int k = 0; k < 3; k++) { /* v = v J */
                    double vkp = v[k][p], vkq = v[k][q];
                    v[k][p] = c * vkp - s * vkq;
                    v[k][q] = s * vkp + c * vkq;
                }
            }
    }
    /* descending order (an even permutation or a sign flip keeps det +1) */
    int o[3] = {0, 1, 2};
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2 - i; j++)
            if (m[o[j]][o[j]] < m[o[j + 1]][o[j + 1]]) {
                int t = o[j];
                o[j] = o[j + 1];
                o[j + 1] = t;
            }
    for (int k = 0; k < 3; k++) {
        val[k] = m[o[k]][o[k]];
        for (int r = 0; r < 3; r++) vec[3 * r + k] = v[r][o[k]];
    }
    double det = vec[0] * (vec[4] * vec[8] - vec[5] * vec[7]) - vec[1] * (vec[3] * vec[8] - vec[5] * vec[6]) +
                 vec[2] * (vec[3] * vec[7] - vec[4] * vec[6]);
    if (det < 0.0)
        for (int r = 0; r < 3; r++) vec[3 * r + 2] = -vec[3 * r + 2];
}

/* smooth_plan.c - the step sizes of N smoothing iterations in fewer passes: super time stepping cycles, then plain steps. */
#include "post/smooth.h"

/*
 * N iterations of Laplacian smoothing (or of normal averaging) are N
 * explicit steps of size 1 of a diffusion whose operator's eigenvalues lie
 * in [0, 2]: 1 is the largest stable step. Super time stepping (Alexiades,
 * Amiez and Gremaud 1996) reaches the same diffusion time N in cycles of k
 * steps whose sizes sum to about k^2 / 3 (damping nu = 0.02: every
 * frequency still decays over a cycle), taken large and small alternately
 * (within a cycle no mode grows more than about 20-fold, harmless in
 * float). The plan: 2 plain steps at the end (they damp the highest
 * frequencies the cycles leave, which matter to the shading), the rest in
 * the fewest cycles of at most 10 steps, each cycle's sizes scaled down to
 * its share. So --smooth 25 makes 9 passes that smooth as much as 25
 * plain steps, splashsurf's 25 iterations in bulk fluid. Only the state
 * after a whole cycle (and after each plain step) is a smoothing of the
 * mesh: within a cycle some modes are amplified, so the bounded smoothing
 * clamps only there (sm_plan_settled).
 */
#define STS_NU 0.02
#define STS_KMAX 10
#define PLAIN_END 2

/* The k step sizes of one cycle, descending; returns their sum. */
static double cycle(int k, double *t)
{
    double sum = 0.0;
    for (int j = 0; j < k; j++) {
        t[j] = 1.0 / ((STS_NU - 1.0) * cos((2.0 * j + 1.0) * M_PI / (2.0 * k)) + 1.0 + STS_NU);
        sum += t[j];
    }
    return sum;
}

int sm_plan(int n, jm_mem *mem, float **out, int *cycle_steps)
{
    *out = NULL;
    *cycle_steps = 0;
    if (n <= 0) return 0;
    double t[STS_KMAX];
    const double tmax = cycle(STS_KMAX, t);
    const int plain = n <= PLAIN_END + 2 ? n : PLAIN_END, rest = n - plain;
    const int cycles = rest > 0 ? (int)ceil((double)rest / tmax) : 0;
    /* the fewest steps per cycle whose sizes reach its share */
    const double share = cycles ? (double)rest / cycles : 0.0;
    int k = 1;
    while (k < STS_KMAX && cycle(k, t) < share) k++;
    const double scale = cycles ? share / cycle(k, t) : 0.0;
    const int total = cycles * k + plain;
    float *tau = jm_alloc(mem, (size_t)total * sizeof *tau);
    if (!tau) return -1;
    int o = 0;
    for (int c = 0; c < cycles; c++) {
        int lo = 0, hi = k - 1; /* t[] is descending: from both ends */
        while (lo <= hi) {
            tau[o++] = (float)(scale * t[lo++]);
            if (lo <= hi) tau[o++] = (float)(scale * t[hi--]);
        }
    }
    while (o < total) tau[o++] = 1.0f;
    *out = tau;
    *cycle_steps = cycles ? k : 0;
    return total;
}

int sm_plan_settled(int it, int total, int cycle_steps, int n)
{
    const int plain = n <= PLAIN_END + 2 ? n : PLAIN_END;
    return it >= total - plain ? 1 : (cycle_steps > 0 && (it + 1) % cycle_steps == 0) ? 2 : 0;
}

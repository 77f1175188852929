/* scenes.h - deterministic synthetic particle scenes: the liquid jet, a jittered block, an isolated spray. */
#ifndef JETMESH_CLI_SCENES_H
#define JETMESH_CLI_SCENES_H

#include <stddef.h>
#include <stdint.h>

/*
 * Every scene is a pure function of its arguments: no clock, no rand(),
 * only integer hashing and IEEE double arithmetic, so the same call gives
 * the same particles on every machine (print them with "%.6f").
 * Units are world units; r is the particle radius.
 */

#define SCENE_DEFAULT_RADIUS 0.025
#define SCENE_PI_L 3.14159265358979323846
#define SCENE_JET_PARTICLES 125 /* particles in the whole jet */
#define SCENE_JET_FRAMES 100    /* the jet's last particle leaves the nozzle in frame 99 */

/** Particles of a scene, malloc'd: 3 floats per particle. */
typedef struct scene_points {
    float *xyz;
    size_t count;
} scene_points;

/**
 * The liquid jet of the 2015 metasphere paper, frame `frame` (>= 0): a
 * nozzle at the origin shoots particles along +x, one every 2.5 ms at
 * v0 = 1.5 r / 2.5 ms (15 m/s for r = 0.025), so they leave it 1.5 r apart
 * and merge into one column. Each particle's speed carries a 2 % sinusoidal
 * perturbation of wavelength 6 particles (9 r, the Rayleigh-Plateau
 * optimum for a jet of radius r): faster particles catch up with slower
 * ones, which makes the column neck and break into droplets downstream;
 * particles that catch up stop 0.7 r behind the one ahead and spread
 * sideways. Gravity (9.81 m/s^2 scaled by r / 0.025) pulls along -y.
 * Frame f is t = 1.25 (f + 0.5) emission intervals after the first
 * particle left: frame 0 has 1 particle, frame 99 all 125; later frames
 * keep the newest 125. Returns 0, or -1 if out of memory.
 */
int scene_jet(int frame, double r, scene_points *out);

/**
 * n particles on a cubic lattice of spacing 2r (x fastest, then y, then
 * z, ceil(cbrt(n)) per side, centred on the origin), each moved by a
 * deterministic jitter of up to 0.1 r per axis from seed. 0 or -1.
 */
int scene_block(size_t n, double r, uint64_t seed, scene_points *out);

/**
 * n isolated droplets: one particle in each of n cells, chosen from seed,
 * of a grid of 12 r cells holding at least 2n, jittered by up to 2 r per
 * axis, so any two particles are at least 8 r apart (twice the largest
 * default kernel support, 4 r): every particle meshes as its own sphere.
 * 0 or -1.
 */
int scene_spray(size_t n, double r, uint64_t seed, scene_points *out);

/**
 * A ball of n particles centred on the origin (scenes_liquid.c), packed at
 * random: points uniform in the ball whose radius holds n at the density
 * of a cubic lattice of spacing 2r, each kept when at least 1.6 r from
 * those kept before (fewer than n if 60 n candidates do not reach it).
 * Its true surface is a sphere: a lattice cut by a sphere has facets. 0 or -1.
 */
int scene_ball(size_t n, double r, uint64_t seed, scene_points *out);

/**
 * n groups of particles 24 r apart on a cubic grid, the smoothing's hard
 * cases (scenes_liquid.c), kind g % 5 for group g: a single particle; a
 * pair 1.4 r to 2.2 r apart; a dense cluster of 5 to 10 particles within
 * 1.2 r of its centre (as splashes make them); a line of 3 to 6 particles
 * 1.6 r to 2 r apart; a cluster of 7 hanging by a neck of two particles
 * from a sheet of two layers of 6 x 6. 0 or -1.
 */
int scene_droplets(size_t n, double r, uint64_t seed, scene_points *out);

/** Frees the particles and zeroes *p. NULL is allowed. */
void scene_points_free(scene_points *p);

/** splitmix64 finaliser: the integer hash every scene draws from. */
uint64_t scene_hash(uint64_t x);

#endif

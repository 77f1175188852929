/* shard.h - --shard I/N: which of a run's frames this process converts when N processes share them. */
#ifndef JETMESH_CLI_SHARD_H
#define JETMESH_CLI_SHARD_H

#include <stddef.h>

/*
 * Shares are interleaved: of the frames the inputs and --frames select, in
 * the order a single run converts them, shard I (0 <= I < N) takes
 * positions I, I+N, I+2N... Interleaving keeps the shards' loads even when
 * the cost of a frame drifts along a sequence (a simulation's particle
 * count grows or a splash spreads), which contiguous blocks would hand to
 * one node; and each shard still writes its outputs in frame order. Every
 * shard must select the same frames (a printf pattern with --frames names
 * them exactly, whatever is on disk yet).
 */
typedef struct shard_spec {
    long index; /* I, from 0 */
    long count; /* N; 0 = no --shard (the whole run) */
} shard_spec;

/** Parses "I/N" (0 <= I < N <= 1000000) or "slurm" (I = SLURM_ARRAY_TASK_ID
 *  minus SLURM_ARRAY_TASK_MIN, N = SLURM_ARRAY_TASK_COUNT, the array's step
 *  1). 0, or -1 with a message. */
int shard_parse(const char *text, shard_spec *out, char *err, size_t errlen);

/** 1 if the frame at position pos (from 0) of the run belongs to s. */
int shard_owns(const shard_spec *s, size_t pos);

#endif

/* fuzz_common.h - the shared body of the reader fuzz targets: read from memory, check the result's invariants. */
#ifndef JETMESH_FUZZ_COMMON_H
#define JETMESH_FUZZ_COMMON_H

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "../../formats/reader.h"

/* 1 if a message tail (after the file name) starts with ":LINE:" or ": byte N", or is about an empty file. */
static int fuzz_has_location(const char *m)
{
    if (m[0] == ':' && m[1] >= '0' && m[1] <= '9') {
        m++;
        while (*m >= '0' && *m <= '9') m++;
        return *m == ':';
    }
    if (strncmp(m, ": byte ", 7) == 0) return m[7] >= '0' && m[7] <= '9';
    return strstr(m, "empty file") != NULL;
}

/* Reads data as fmt (named name, which also gives the extension for auto)
 * with and without drop_invalid and aborts on any broken invariant. */
static void fuzz_read(const uint8_t *data, size_t size, jmf_input_format fmt, const char *name)
{
    int drop;
    for (drop = 0; drop < 2; drop++) {
        jmf_read_options opt;
        jmf_frame fr;
        char err[512];
        jmf_status st;
        size_t i;
        memset(&opt, 0, sizeof opt);
        opt.format = fmt;
        opt.drop_invalid = drop;
        opt.max_bytes = 64u << 20; /* keeps decompression bombs within the RSS limit */
        memset(err, 'x', sizeof err);
        st = jmf_read_particles_mem(data, size, name, &opt, &fr, err, sizeof err);
        if ((int)st < 0 || st > JMF_E_LIMIT) abort();
        if (!memchr(err, '\0', sizeof err)) abort();
        if (st != JMF_OK) {
            size_t n = strlen(err);
            if (n == 0 || strncmp(err, name, strlen(name)) != 0) abort();
            if (strchr(err, '\n') || strchr(err, '\r')) abort();
            if (fr.xyz || fr.ids || fr.count || fr.dropped) abort();
            if (st == JMF_E_FORMAT && !fuzz_has_location(err + strlen(name))) abort();
            continue;
        }
        if (err[0] != '\0') abort();
        if ((fr.count == 0) != (fr.xyz == NULL)) abort();
        if (fr.ids && fr.count == 0) abort();
        if (!drop && fr.dropped) abort();
        for (i = 0; i < 3 * fr.count; i++)
            if (!isfinite(fr.xyz[i])) abort();
        if (fr.ids) {
            volatile uint32_t sum = 0;
            for (i = 0; i < fr.count; i++) sum += fr.ids[i];
            (void)sum;
        }
        if (fmt != JMF_IN_AUTO && fr.format != fmt) abort();
        jmf_frame_free(&fr);
    }
}

#endif

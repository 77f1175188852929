/* shared_data.h - test helper: reads a particle frame from the shared data folder (../shared/data or $JETMESH_SHARED/data). */
#ifndef JETMESH_TESTS_SHARED_DATA_H
#define JETMESH_TESTS_SHARED_DATA_H

#include <stddef.h>

#include "../../formats/reader.h"

/* Reads DATA/rel, DATA being $JETMESH_SHARED/data (else ../shared/data),
 * with opt (NULL: the defaults) into *fr. 1: read; 0: the file cannot be
 * opened (the shared data is not here: skip); -1: any other failure, with
 * the reader's message in err. */
int test_read_shared(const char *rel, const jmf_read_options *opt, jmf_frame *fr, char *err, size_t errlen);

#endif

/* progress.h - a one-line progress bar on stderr (frames done/total, frames/s, ETA), only on a terminal. */
#ifndef JETMESH_CLI_PROGRESS_H
#define JETMESH_CLI_PROGRESS_H

#include <stddef.h>

typedef struct progress {
    int enabled;       /* 0: every call does nothing */
    size_t total;
    size_t done;
    double start_ms;
    double last_draw_ms;
    int drawn;         /* a bar is on the screen */
} progress;

/** Enabled only if want is set and stderr is a terminal. */
void progress_init(progress *p, size_t total, int want);

/** Records that `done` frames are finished and redraws (at most 10 times a second). */
void progress_update(progress *p, size_t done);

/** Erases the bar (before printing a line), if one is drawn. */
void progress_clear(progress *p);

/** Redraws the bar now (after printing a line). */
void progress_redraw(progress *p);

/** Erases the bar for good. */
void progress_finish(progress *p);

#endif

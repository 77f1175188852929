/* stdout_check.h - a write error on standard output is reported once and fails the run. */
#ifndef JETMESH_CLI_STDOUT_CHECK_H
#define JETMESH_CLI_STDOUT_CHECK_H

/* The lines on standard output are what scripts parse: losing them to a
 * full disk or /dev/full is an error (issue 30: `> /dev/full` exited 0). */

/** Flushes standard output; on a write error, prints why on standard
 *  error (once per process). 0 when it is fine, -1 after an error. */
int stdout_check(void);

/** The exit status of a command that returned rc: rc, or 1 (some output
 *  failed) when standard output could not be written and rc was 0. */
int stdout_finish(int rc);

#endif

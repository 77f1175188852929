/* signals.h - SIGINT/SIGTERM/SIGHUP/SIGPIPE handling: remove unfinished output temporaries, then die by the signal. */
#ifndef JETMESH_CLI_SIGNALS_H
#define JETMESH_CLI_SIGNALS_H

/** Blocks the signals and starts the thread that takes them (the design is
 *  at the top of signals.c). Call it first, before any other thread is
 *  started, so that every thread inherits the mask. On a signal:
 *  jmf_atomic_shutdown(), then death by that signal (status 130 for
 *  SIGINT, 143 for SIGTERM, 129 for SIGHUP). A signal that was ignored when
 *  jetmesh started stays ignored. Calling it again does nothing. */
void signals_install_cleanup(void);

#endif

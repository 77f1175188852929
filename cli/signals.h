/* signals.h - SIGINT/SIGTERM/SIGHUP/SIGPIPE handling: remove unfinished output temporaries, then die by the signal. */
#ifndef JETMESH_CLI_SIGNALS_H
#define JETMESH_CLI_SIGNALS_H

/** Installs the handlers. On the signal: jmf_atomic_remove_pending(), then
 *  the default action is restored and the signal raised again, so the
 *  shell sees death by that signal (status 130 for SIGINT, 143 for SIGTERM).
 *  A signal that was ignored when jetmesh started (nohup, a background job
 *  of a non-interactive shell) stays ignored. */
void signals_install_cleanup(void);

#endif

/* templates.h - isolated particles meshed as copies of one particle's mesh (the template), translated. */
#ifndef JETMESH_TEMPLATES_H
#define JETMESH_TEMPLATES_H
#include "frame.h"

/* The template at each of f's isolated particles (f->iso_pos), after the
 * lattice's mesh: its first vertex and index in f->tmpl_v0, f->tmpl_i0. */
jm_status jm_frame_templates(jm_frame *f);
#endif

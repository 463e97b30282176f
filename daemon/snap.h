/* snap.h - save/restore: the full simulation state and parameters in a
 * named text file under the state directory.
 *
 * The file holds every parameter by name and every state number as a C99
 * hex float (%a), so a restore continues bit-exactly where the save was
 * taken (same trajectory, same ramp). Names are [A-Za-z0-9_.-], 1-64
 * characters, not starting with '.': no '/', no "..". The file is
 * NAME.wgstate, written to a temporary file and renamed (never half a file).
 * What makes up the state is the library's business (wg_snapshot). */
#ifndef WGD_SNAP_H
#define WGD_SNAP_H

#include <stddef.h>
#include <stdint.h>

#include "wormgear/wg_sim.h"

typedef struct snap {
    char scene[64];
    wg_snapshot w; /* the library's run state (wg_sim_snapshot/restore) */
} snap;

/* 0 if name is an acceptable snapshot name, else WG_EINVAL with why. */
int snap_name_ok(const char *name, char *why, size_t whylen);

/* Capture sim (and the scene name) into s. */
void snap_take(snap *s, const wg_sim *sim, const char *scene);

/* Write s to dir/NAME.wgstate (dir created if missing). WG_OK, WG_EINVAL
 * (name) or WG_EIO with why; *path receives the file name. */
int snap_write(const snap *s, const char *dir, const char *name, char *path, size_t pathlen,
               char *why, size_t whylen);

/* Read and validate dir/NAME.wgstate: every parameter through the table.
 * WG_OK, WG_EINVAL (name, syntax), WG_EIO (missing), WG_EUNKNOWN, WG_ERANGE
 * with why ("file:line: ..."). */
int snap_read(snap *s, const char *dir, const char *name, char *why, size_t whylen);

/* Apply s to sim, atomically: WG_ESTATE if the model, stepper or N differ
 * from the running sim, WG_ERANGE/WG_ESTABILITY from wg_sim_set_params;
 * sim unchanged on error. */
int snap_apply(const snap *s, wg_sim *sim, char *why, size_t whylen);

#endif

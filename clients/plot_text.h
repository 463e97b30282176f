/* plot_text.h - the words on a figure that the numbers behind it decide:
 * a parameter's axis label with symbol and unit, its physical second
 * scale (omega -> mesh frequency in Hz, lengths -> µm, from the scene's
 * scale and units.h), and the caption lines every figure carries (scene,
 * ξ_p and every parameter set away from the scene, N, transient and
 * recorded periods). No cairo: wgsweep's writers fill plot.h's structs. */
#ifndef WG_PLOT_TEXT_H
#define WG_PLOT_TEXT_H

#include <stddef.h>
#include "plot.h"
#include "units.h"
#include "wormgear/wg_sweep.h"

/* The x_n axis labels: in b_c, and in µm. */
#define PLOT_XN_LABEL "x_n  (b_c)"
#define PLOT_XN_UM "x_n  (µm)"

/* The symbol of parameter id: "ω", "ξ_p", else its name. */
const char *plot_text_psym(int id);

/* Axis label of parameter id: "ω = mesh frequency / ω_n  (-)",
 * "ξ_p = mesh damping ratio  (-)", "k_a  (-)", "phi1  (rad)". Returns buf. */
const char *plot_text_plabel(int id, char *buf, size_t len);

/* The physical second scale of parameter id at values p ("mesh frequency
 * (Hz)" for omega, "b  (µm)" for b ...), the label in buf; {0} when it has
 * none (or the scale is not usable). */
plot_scale2 plot_text_pscale(int id, const wg_params *p, const units_scale *s, char *buf,
                             size_t len);

/* The caption of a figure made from parameters p of scene `scene` (its own
 * values scene_p), the parameters swept and swept2 (-1: none) not listed
 * as set:
 *   cap[0] "scene table3, ξ_p = 0.08, N = 256 steps per mesh period,
 *           transient 300 periods (+ up to 3 x 300 while no period is
 *           found), 128 periods recorded"
 *   cap[1] "set away from the scene: f_e = 0.1 (scene: 0.0924)" or
 *          "every parameter as in the scene".
 * nmin..nmax: the N the points used (0: o->steps). */
void plot_text_caption(char cap[2][400], const char *scene, const wg_params *p,
                       const wg_params *scene_p, int swept, int swept2, const wg_sweep_opts *o,
                       int nmin, int nmax);

/* As plot_text_caption, with run in place of the transient and recorded
 * periods when not NULL: what a run did that has no per-point settle and
 * record (wgrig --ramp: "ramp ω 0.5 → 1 and back over 2 s simulated each
 * way (≈ 11000 mesh periods), every section binned onto 25 values"). */
void plot_text_caption_run(char cap[2][400], const char *scene, const wg_params *p,
                           const wg_params *scene_p, int swept, int swept2,
                           const wg_sweep_opts *o, int nmin, int nmax, const char *run);

/* The scale of a scene as units.h takes it. */
units_scale plot_text_scale(double omega_n_rad_s, double length_m, double stiffness_N_m);

/* The file extension of a format: "png" for NULL. */
const char *plot_text_ext(const char *format);

#endif

/* plot_text.c - labels, second scales and captions of figures (see
 * plot_text.h). */
#include "plot_text.h"

#include <stdio.h>
#include <string.h>

const char *plot_text_psym(int id)
{
    const wg_param_info *r = wg_param_info_get(id);
    return id == WG_P_OMEGA ? "ω" : id == WG_P_XI_P ? "ξ_p" : r ? r->name : "?";
}

const char *plot_text_plabel(int id, char *buf, size_t len)
{
    const wg_param_info *r = wg_param_info_get(id);
    if (id == WG_P_OMEGA)
        snprintf(buf, len, "ω = mesh frequency / ω_n  (-)");
    else if (id == WG_P_XI_P)
        snprintf(buf, len, "ξ_p = mesh damping ratio  (-)");
    else if (r)
        snprintf(buf, len, "%s  (%s)", r->name, wg_unit_shown(r->unit));
    else
        snprintf(buf, len, "?");
    return buf;
}

plot_scale2 plot_text_pscale(int id, const wg_params *p, const units_scale *s, char *buf,
                             size_t len)
{
    double k;
    const char *unit;
    if (units_param_factor(id, p, s, &k, &unit))
        return (plot_scale2){0, NULL, 0};
    if (id == WG_P_OMEGA)
        snprintf(buf, len, "mesh frequency  (%s)", unit);
    else if (id == WG_P_XI_P)
        snprintf(buf, len, "mesh damping coefficient  (%s)", unit);
    else
        snprintf(buf, len, "%s  (%s)", wg_param_info_get(id)->name, unit);
    return (plot_scale2){k, buf, 0};
}

void plot_text_caption(char cap[2][400], const char *scene, const wg_params *p,
                       const wg_params *scene_p, int swept, int swept2, const wg_sweep_opts *o,
                       int nmin, int nmax)
{
    plot_text_caption_run(cap, scene, p, scene_p, swept, swept2, o, nmin, nmax, NULL);
}

void plot_text_caption_run(char cap[2][400], const char *scene, const wg_params *p,
                           const wg_params *scene_p, int swept, int swept2,
                           const wg_sweep_opts *o, int nmin, int nmax, const char *run)
{
    char xi[48], n[64], ext[96] = "", early[64] = "";
    if (swept == WG_P_XI_P || swept2 == WG_P_XI_P)
        snprintf(xi, sizeof xi, "ξ_p swept");
    else
        snprintf(xi, sizeof xi, "ξ_p = %g", p->v[WG_P_XI_P]);
    if (nmin <= 0)
        nmin = nmax = o->steps;
    if (nmax > nmin)
        snprintf(n, sizeof n, "N = %d..%d steps per mesh period", nmin, nmax);
    else
        snprintf(n, sizeof n, "N = %d steps per mesh period", nmin);
    if (o->extend > 0)
        snprintf(ext, sizeof ext, " (+ up to %d x %d while no period is found)", o->extend,
                 o->transient);
    if (o->settle > 0)
        snprintf(early, sizeof early, " or fewer, ending once settled over %d", o->settle);
    if (run)
        snprintf(cap[0], 400, "scene %s, %s, %s, %s", scene, xi, n, run);
    else
        snprintf(cap[0], 400, "scene %s, %s, %s, transient %d periods%s%s, %d periods recorded",
                 scene, xi, n, o->transient, early, ext, o->record);
    int len = snprintf(cap[1], 400, "set away from the scene:"), shown = 0;
    for (int id = 0; id < WG_NPARAM && len < 330; id++)
        if (id != swept && id != swept2 && id != WG_P_XI_P && p->v[id] != scene_p->v[id])
            len += snprintf(cap[1] + len, (size_t)(400 - len), "%s %s = %g (scene: %g)",
                            shown++ ? "," : "", plot_text_psym(id), p->v[id],
                            scene_p->v[id]);
    if (p->v[WG_P_XI_P] != scene_p->v[WG_P_XI_P] && swept != WG_P_XI_P &&
        swept2 != WG_P_XI_P && len < 330)
        snprintf(cap[1] + len, (size_t)(400 - len), "%s ξ_p (scene: %g)", shown++ ? "," : "",
                 scene_p->v[WG_P_XI_P]);
    if (!shown)
        snprintf(cap[1], 400, "every %sparameter as in the scene", swept >= 0 ? "other " : "");
}

units_scale plot_text_scale(double omega_n_rad_s, double length_m, double stiffness_N_m)
{
    return (units_scale){omega_n_rad_s, length_m, stiffness_N_m};
}

const char *plot_text_ext(const char *format)
{
    return format && *format ? format : "png";
}

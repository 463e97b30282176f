/* sdn.c - sd_notify wrappers. */
#include "sdn.h"

#include "wgd.h"

#include <stdio.h>
#include <systemd/sd-daemon.h>

void sdn_init(sdn *s)
{
    *s = (sdn){0};
    uint64_t usec = 0;
    if (sd_watchdog_enabled(0, &usec) > 0)
        s->wd_usec = usec;
}

void sdn_fini(sdn *s) { (void)s; }

void sdn_ready(sdn *s, const char *line)
{
    sd_notifyf(0, "READY=1\nSTATUS=%s", line);
    s->ready = 1;
}

void sdn_status(const char *line) { sd_notifyf(0, "STATUS=%s", line); }

void sdn_watchdog(sdn *s, int64_t now_ns)
{
    if (!s->wd_usec || now_ns < s->next_wd_ns)
        return;
    sd_notify(0, "WATCHDOG=1");
    s->next_wd_ns = now_ns + (int64_t)s->wd_usec * 250;
}

void sdn_reloading(sdn *s)
{
    sd_notify(0, "RELOADING=1");
    s->ready = 0;
}

void sdn_stopping(void) { sd_notify(0, "STOPPING=1"); }

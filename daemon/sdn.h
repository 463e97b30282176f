/* sdn.h - systemd notification (sd_notify): READY, STATUS, WATCHDOG,
 * RELOADING, STOPPING. Every call is a no-op when not started by systemd
 * (no $NOTIFY_SOCKET). */
#ifndef WGD_SDN_H
#define WGD_SDN_H

#include <stdint.h>

struct sdn;

/* Read the watchdog interval ($WATCHDOG_USEC) if any. */
void sdn_init(struct sdn *s);

/* Nothing to release; sends nothing (STOPPING=1 is sdn_stopping). */
void sdn_fini(struct sdn *s);

/* READY=1 with a STATUS= line (once; again after sdn_reloading). */
void sdn_ready(struct sdn *s, const char *line);

/* STATUS=<line> (systemctl status shows it). */
void sdn_status(const char *line);

/* WATCHDOG=1, at most every quarter of the interval; call from the step path. */
void sdn_watchdog(struct sdn *s, int64_t now_ns);

/* RELOADING=1 (SIGHUP); the next sdn_ready completes it. */
void sdn_reloading(struct sdn *s);

/* STOPPING=1. */
void sdn_stopping(void);

#endif

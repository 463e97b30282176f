/* wg_status.h - return codes shared by the model library, daemon and clients.
 *
 * Every fallible function returns WG_OK (0) or one of the negative codes
 * below; wg_status_name() gives the stable upper-case name used on the wire
 * (ACK messages) and in logs, wg_status_str() a short English phrase. */
#ifndef WG_STATUS_H
#define WG_STATUS_H

enum wg_status {
    WG_OK = 0,
    WG_EINVAL = -1,      /* malformed argument (syntax, not a number, ...) */
    WG_ERANGE = -2,      /* value outside the parameter table's range */
    WG_EUNKNOWN = -3,    /* unknown parameter or key */
    WG_ENONFINITE = -4,  /* integration produced a non-finite or absurd state */
    WG_ESTABILITY = -5,  /* step too large for RK4 on the scene's fastest mode */
    WG_ENOMEM = -6,      /* allocation failed */
    WG_EIO = -7,         /* file could not be read or written */
    WG_ESTATE = -8,      /* operation not allowed in the current state */
    WG_EDECODE = -9,     /* a message could not be decoded */
    WG_EUNSUPPORTED = -10, /* combination of options not supported */
    WG_EAUTH = -11         /* a command not signed, signed with another key, stale or replayed */
};

/* Stable name of a status code ("WG_OK" -> "OK", WG_ERANGE -> "ERANGE");
 * "EUNKNOWNCODE" for a value that is not a status. */
const char *wg_status_name(int code);

/* One-line English description of a status code. */
const char *wg_status_str(int code);

#endif

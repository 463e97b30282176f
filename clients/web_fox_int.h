/* web_fox_int.h - shared by web_fox.c (output side) and web_fox_rx.c
 * (client requests) only. */
#ifndef WEB_FOX_INT_H
#define WEB_FOX_INT_H

#include "web_fox.h"

/* Queue a text frame on client ci's control queue (kicks the client when
 * it is full). */
void fox_ctrl(fox *f, int ci, const char *text, size_t len);

/* Send parameterValues to client ci: the parameters whose snapshot index
 * bit is set in mask (all when all), with request id (NULL: none). */
void fox_param_values(fox *f, int ci, int all, uint64_t mask, const char *id);

/* Snapshot index of parameter name, or -1. */
int fox_param_index(const fox *f, const char *name);

/* A free pending-command slot (the oldest is reused when full). */
fox_pending *fox_pending_new(fox *f);

#endif

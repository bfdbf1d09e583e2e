/* auth_acl: who may publish on which channel (docs/method/lockstep.md §4-5).
 *
 * One const table (auth_acl_table in auth_acl.c) lists every tandem
 * channel with the roles allowed to publish on it; numbered channels
 * (ARMk_COMMAND, ROVERk_STATE, HEALTH_TANDEM_ARM_k ...) can further demand
 * that the sender's instances cover k ("arm k publishes ARMk_COMMAND").
 * A channel the table does not name is refused. The sender id it checks
 * is the one the pairwise key proves (auth.h): a process holding rover 1's
 * key file can only be rover 1. The readers column says which receivers a
 * message carries a tag for.
 */
#ifndef TANDEM_AUTH_ACL_H
#define TANDEM_AUTH_ACL_H

#include "auth.h"

/* How the channel name is matched. */
enum {
    AUTH_ACL_EXACT = 0,  /* channel == prefix */
    AUTH_ACL_NUMBER = 1, /* prefix, a number K, suffix */
    AUTH_ACL_RANGE = 2   /* prefix, K or K_L, suffix (a rover host's health) */
};

#define AUTH_ACL_NUMBER_MAX 65535 /* instances are 16-bit */

typedef struct auth_acl_rule {
    const char *prefix;
    const char *suffix; /* "" for AUTH_ACL_EXACT */
    int match;          /* AUTH_ACL_* */
    unsigned roles;     /* AUTH_ROLE_BIT of every role allowed */
    int own;            /* 1: the sender's [first, last] must cover K..L */
    unsigned readers;   /* AUTH_ROLE_BIT of every role a message is tagged for */
    int readers_own;    /* 1: of the arms, only those covering K..L */
} auth_acl_rule;

extern const auth_acl_rule auth_acl_table[];
extern const int auth_acl_table_n;

/* Named results of the validator. */
enum {
    AUTH_ACL_OK = 0,
    AUTH_ACL_ERR_EMPTY = -1,   /* no rules */
    AUTH_ACL_ERR_NAME = -2,    /* prefix/suffix missing or not [A-Z0-9_] */
    AUTH_ACL_ERR_MATCH = -3,   /* unknown match kind, or an exact rule with a suffix */
    AUTH_ACL_ERR_ROLES = -4,   /* no role, or an unknown role bit */
    AUTH_ACL_ERR_OWN = -5,     /* own on a channel without a number */
    AUTH_ACL_ERR_OVERLAP = -6, /* a channel two rules match */
    AUTH_ACL_ERR_READERS = -7  /* no reader, or an unknown reader role bit */
};

/* AUTH_ACL_OK if the table is well-formed: names, match kinds, roles,
 * and no channel matched by two rules. */
int auth_acl_validate(const auth_acl_rule *t, int n);
/* The rule matching channel (and its K..L in lo, hi; 0 when unnumbered),
 * or NULL. */
const auth_acl_rule *auth_acl_find(const auth_acl_rule *t, int n, const char *channel, long *lo,
                                   long *hi);
/* AUTH_OK if the table lets sender s publish on channel, else AUTH_ERR_ACL. */
int auth_acl_check(const auth_acl_rule *t, int n, const char *channel, const auth_sender *s);
/* The reader roles of channel (0: not in the table). */
unsigned auth_acl_readers(const auth_acl_rule *t, int n, const char *channel);
/* 1 if receiver p gets a tag on channel (its role reads it, and an arm
 * reads a numbered arm channel only of its own number where readers_own). */
int auth_acl_reader_wanted(const auth_acl_rule *t, int n, const char *channel, const auth_peer *p);
/* The sender a channel's legitimate publisher would have (its first
 * allowed role, instances K..L): for a process standing in for several
 * daemons (integration tests, the round-trip bench). AUTH_ERR_ACL for a
 * channel the table does not name. */
int auth_acl_owner(const auth_acl_rule *t, int n, const char *channel, auth_sender *s);

#endif

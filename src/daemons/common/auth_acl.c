/* auth_acl: the channel -> publisher table and its checks (see auth_acl.h). */
#include "auth_acl.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SIM AUTH_ROLE_BIT(AUTH_ROLE_SIM)
#define ARM AUTH_ROLE_BIT(AUTH_ROLE_ARM)
#define SUP AUTH_ROLE_BIT(AUTH_ROLE_SUPERVISOR)
#define ROVER AUTH_ROLE_BIT(AUTH_ROLE_ROVER)
#define TOOL AUTH_ROLE_BIT(AUTH_ROLE_TOOL)
#define MON AUTH_ROLE_BIT(AUTH_ROLE_MONITOR)
#define ALL AUTH_ROLES_ALL

/* README "Channels" lists the same; the first role is the owner
 * auth_acl_owner signs as. Columns: channel, writers, own (a writer's
 * instances must cover K), readers (the roles a message carries a tag
 * for), readers_own (of the arms only arm K: another arm gets no tag it
 * could check, so holds no key that would let it speak as the sender). */
const auth_acl_rule auth_acl_table[] = {
    /* the 1 kHz channels are tagged only for who reads them (a tag per reader) */
    { "SIM_CLOCK", "", AUTH_ACL_EXACT, SIM, 0, ARM | SUP | ROVER | TOOL | MON, 0 },
    { "SIM_STATUS", "", AUTH_ACL_EXACT, SIM, 0, ALL, 0 },
    { "SIM_CONTROL", "", AUTH_ACL_EXACT, TOOL, 0, ALL, 0 },
    /* lockstep participants: the daemons, scenarios and tests */
    { "SIM_ACK", "", AUTH_ACL_EXACT, ARM | SUP | ROVER | TOOL, 0, ALL, 0 },
    { "ARM", "_STATE", AUTH_ACL_NUMBER, SIM, 0, ARM | TOOL | MON, 1 },
    { "ARM", "_COMMAND", AUTH_ACL_NUMBER, ARM, 1, SIM | TOOL | MON, 0 },
    { "ARM", "_ACTION", AUTH_ACL_NUMBER, SUP, 0, ARM | TOOL | MON, 1 },
    { "ARM", "_JOINT_REF", AUTH_ACL_NUMBER, TOOL, 0, ARM | TOOL | MON,
      1 }, /* an external resolver (TDSD scenarios) */
    { "ARM_EVENTS", "", AUTH_ACL_EXACT, ARM, 0, ALL, 0 },
    { "PETRI_MARKING", "", AUTH_ACL_EXACT, SUP, 0, ALL, 0 },
    { "VISION_DETECTIONS", "", AUTH_ACL_EXACT, SIM, 0, ALL, 0 },
    { "ROVER", "_SENSORS", AUTH_ACL_NUMBER, SIM, 0, ALL, 0 },
    { "ROVER", "_SONAR", AUTH_ACL_NUMBER, SIM, 0, ALL, 0 },
    { "ROVER", "_BEACONS", AUTH_ACL_NUMBER, SIM, 0, ALL, 0 },
    { "ROVER", "_COMMAND", AUTH_ACL_NUMBER, ROVER, 1, ALL, 0 },
    { "ROVER", "_STATE", AUTH_ACL_NUMBER, ROVER, 1, ALL, 0 },
    { "ROVERS_SENSORS", "", AUTH_ACL_EXACT, SIM, 0, ALL, 0 },
    { "ROVERS_BEACONS", "", AUTH_ACL_EXACT, SIM, 0, ALL, 0 },
    { "ROVERS_COMMAND", "", AUTH_ACL_EXACT, ROVER, 0, ALL, 0 },
    { "ROVERS_STATE", "", AUTH_ACL_EXACT, ROVER, 0, ALL, 0 },
    { "TEAM", "", AUTH_ACL_EXACT, ROVER, 0, ALL, 0 },
    { "TEAMS", "", AUTH_ACL_EXACT, ROVER, 0, ALL, 0 },
    { "ROVER_TRUTH", "", AUTH_ACL_EXACT, SIM, 0, ALL, 0 },
    /* each daemon its own health channel (daemon_start names it) */
    { "HEALTH_TANDEM_SIM", "", AUTH_ACL_EXACT, SIM, 0, ALL, 0 },
    { "HEALTH_TANDEM_SUPERVISOR", "", AUTH_ACL_EXACT, SUP, 0, ALL, 0 },
    { "HEALTH_TANDEM_ARM_", "", AUTH_ACL_NUMBER, ARM, 1, ALL, 0 },
    { "HEALTH_TANDEM_ROVER_", "", AUTH_ACL_RANGE, ROVER, 1, ALL, 0 },
};
const int auth_acl_table_n = (int)(sizeof auth_acl_table / sizeof auth_acl_table[0]);

#define AUTH_ACL_MAX_RULES 256

/* Reads a decimal number of 1-5 digits at *p (moving *p past it). */
/* read_number: no digits, more than 5, or above AUTH_ACL_NUMBER_MAX */
#define NUMBER_BAD (-1)

static int read_number(const char **p, long *v)
{
    const char *s = *p;
    int n = 0;
    *v = 0;
    while (*s >= '0' && *s <= '9' && n < 6) {
        *v = *v * 10 + (*s - '0');
        s++;
        n++;
    }
    if (n < 1 || n > 5 || *v > AUTH_ACL_NUMBER_MAX)
        return NUMBER_BAD;
    *p = s;
    return 0;
}

static int rule_matches(const auth_acl_rule *r, const char *channel, long *lo, long *hi)
{
    const size_t np = strlen(r->prefix);
    const char *p = channel + np;
    *lo = *hi = 0;
    if (strncmp(channel, r->prefix, np) != 0)
        return 0;
    if (r->match == AUTH_ACL_EXACT)
        return *p == '\0';
    if (read_number(&p, lo) != 0)
        return 0;
    *hi = *lo;
    if (r->match == AUTH_ACL_RANGE && p[0] == '_' && p[1] >= '0' && p[1] <= '9') {
        p++;
        if (read_number(&p, hi) != 0 || *hi < *lo)
            return 0;
    }
    return strcmp(p, r->suffix) == 0;
}

const auth_acl_rule *auth_acl_find(const auth_acl_rule *t, int n, const char *channel, long *lo,
                                   long *hi)
{
    int i;
    for (i = 0; i < n; i++)
        if (rule_matches(&t[i], channel, lo, hi))
            return &t[i];
    return NULL;
}

int auth_acl_check(const auth_acl_rule *t, int n, const char *channel, const auth_sender *s)
{
    long lo, hi;
    const auth_acl_rule *r = auth_acl_find(t, n, channel, &lo, &hi);
    if (!r || s->role > AUTH_ROLE_LAST || !(r->roles & AUTH_ROLE_BIT(s->role)))
        return AUTH_ERR_ACL;
    if (r->own && (lo < s->first || hi > s->last))
        return AUTH_ERR_ACL;
    return AUTH_OK;
}

unsigned auth_acl_readers(const auth_acl_rule *t, int n, const char *channel)
{
    long lo, hi;
    const auth_acl_rule *r = auth_acl_find(t, n, channel, &lo, &hi);
    return r ? r->readers : 0u;
}

int auth_acl_reader_wanted(const auth_acl_rule *t, int n, const char *channel, const auth_peer *p)
{
    long lo, hi;
    const auth_acl_rule *r = auth_acl_find(t, n, channel, &lo, &hi);
    if (!r || p->role > AUTH_ROLE_LAST || !(r->readers & AUTH_ROLE_BIT(p->role)))
        return 0;
    if (r->readers_own && p->role == AUTH_ROLE_ARM)
        return lo >= p->first && hi <= p->last;
    return 1;
}

int auth_acl_owner(const auth_acl_rule *t, int n, const char *channel, auth_sender *s)
{
    long lo, hi;
    int role;
    const auth_acl_rule *r = auth_acl_find(t, n, channel, &lo, &hi);
    if (!r)
        return AUTH_ERR_ACL;
    for (role = AUTH_ROLE_SIM; role <= AUTH_ROLE_LAST; role++)
        if (r->roles & AUTH_ROLE_BIT(role))
            break;
    s->role = (uint8_t)role;
    s->first = (uint16_t)lo;
    s->last = (uint16_t)hi;
    return AUTH_OK;
}

/* ---- validator ----------------------------------------------------------------- */

static int name_ok(const char *s, int may_be_empty)
{
    if (!s || (!may_be_empty && !s[0]) || strlen(s) > AUTH_CHANNEL_MAX)
        return 0;
    for (; *s; s++)
        if (!((*s >= 'A' && *s <= 'Z') || (*s >= '0' && *s <= '9') || *s == '_'))
            return 0;
    return 1;
}

static int rule_ok(const auth_acl_rule *r)
{
    if (!name_ok(r->prefix, 0) || !name_ok(r->suffix, 1))
        return AUTH_ACL_ERR_NAME;
    if (r->match < AUTH_ACL_EXACT || r->match > AUTH_ACL_RANGE ||
        (r->match == AUTH_ACL_EXACT && r->suffix[0]))
        return AUTH_ACL_ERR_MATCH;
    if (r->roles == 0 || (r->roles & ~AUTH_ROLES_ALL) != 0)
        return AUTH_ACL_ERR_ROLES;
    if ((r->own != 0 && r->own != 1) || (r->own && r->match == AUTH_ACL_EXACT))
        return AUTH_ACL_ERR_OWN;
    if (r->readers == 0 || (r->readers & ~AUTH_ROLES_ALL) != 0)
        return AUTH_ACL_ERR_READERS;
    if ((r->readers_own != 0 && r->readers_own != 1) ||
        (r->readers_own && r->match == AUTH_ACL_EXACT))
        return AUTH_ACL_ERR_OWN;
    return AUTH_ACL_OK;
}

/* A channel the rule matches: numbers 7 (and 7_9 for a range). */
static void sample_channel(const auth_acl_rule *r, int range, char *out, size_t cap)
{
    snprintf(out, cap, "%s%s%s", r->prefix,
             r->match == AUTH_ACL_EXACT ? ""
             : range                    ? "7_9"
                                        : "7",
             r->suffix);
}

static int matched_by_one(const auth_acl_rule *t, int n, const char *channel)
{
    long lo, hi;
    int i, hits = 0;
    for (i = 0; i < n; i++)
        hits += rule_matches(&t[i], channel, &lo, &hi);
    return hits == 1;
}

int auth_acl_validate(const auth_acl_rule *t, int n)
{
    int i, rc;
    char ch[2 * AUTH_CHANNEL_MAX + 8];
    if (!t || n < 1 || n > AUTH_ACL_MAX_RULES)
        return AUTH_ACL_ERR_EMPTY;
    for (i = 0; i < n; i++)
        if ((rc = rule_ok(&t[i])) != AUTH_ACL_OK)
            return rc;
    for (i = 0; i < n; i++) {
        sample_channel(&t[i], 0, ch, sizeof ch);
        if (!matched_by_one(t, n, ch))
            return AUTH_ACL_ERR_OVERLAP;
        sample_channel(&t[i], 1, ch, sizeof ch);
        if (t[i].match == AUTH_ACL_RANGE && !matched_by_one(t, n, ch))
            return AUTH_ACL_ERR_OVERLAP;
    }
    return AUTH_ACL_OK;
}

/* petri: Petri-net engine for the discrete-event supervisor (docs/method/carry.md §5,
 * eq. 11) and a bounded reachability explorer.
 *
 * A net is const tables: N- (input), N+ (output) and optionally an
 * inhibitor table, each n_places x n_transitions, row-major
 * (entry [i * n_transitions + j] is place i, transition j), entries 0/1.
 * An inhibitor arc (i, j) means t_j may start only while place i is
 * empty: this models external token sources such as the vision system
 * adding a workpiece token to p1 only while p1 is empty.
 *
 * Indices are 0-based in C (t_1 of the seed is transition 0).
 *
 * Split firing: petri_start(t) removes the input tokens (the action
 * starts) and marks t running; petri_complete(t) adds the output tokens
 * (its completion event). A running transition cannot start again.
 * petri_fire = start + complete = eq. 11, gamma(k) = gamma(k-1) + N t_j.
 *
 * P-invariants y (y^T N = 0) are checked with the tokens of running
 * transitions counted at their input places (they are "in flight"):
 *   y^T gamma + sum_{j running} y^T N-_j = y^T gamma0.
 */
#ifndef TANDEM_PETRI_H
#define TANDEM_PETRI_H

#include <stdint.h>

#define PETRI_MAX_PLACES 32      /* one bit each in a uint32_t mask */
#define PETRI_MAX_TRANSITIONS 32 /* running set is a uint32_t mask  */
#define PETRI_MAX_INVARIANTS 8
#define PETRI_TOKEN_MAX 255
#define PETRI_MAX_STATES 4096 /* reachability: visited-set capacity */
#define PETRI_HASH_SIZE 8192  /* power of two, > PETRI_MAX_STATES   */

#define PETRI_ERR_ARG (-1)          /* bad argument / index            */
#define PETRI_ERR_NOT_ENABLED (-2)  /* start of a transition not enabled */
#define PETRI_ERR_NOT_RUNNING (-3)  /* completion of one not running   */
#define PETRI_ERR_OVERFLOW (-4)     /* a place would exceed PETRI_TOKEN_MAX */
#define PETRI_ERR_NONE_ENABLED (-9) /* petri_select: no transition enabled */
/* petri_net_validate only (petri_compile returns PETRI_ERR_ARG for the
 * first two): */
#define PETRI_ERR_SIZE \
    (-5)                     /* places / transitions / invariants
                                       outside 1..PETRI_MAX_* (0.. for
                                       invariants)                     */
#define PETRI_ERR_ENTRY (-6) /* an N-, N+ or inhibitor entry not 0/1 */
#define PETRI_ERR_TRANSITION \
    (-7) /* a transition that can never act: no
                                       arc at all, or an inhibitor arc on
                                       one of its own input places      */
#define PETRI_ERR_INVARIANT \
    (-8) /* an invariant y that is zero or not a
                                       P-invariant (y^T N != 0, N = N+ - N-) */

typedef struct {
    int n_places;
    int n_transitions;
    const int8_t *n_minus;   /* rho x tau, 0/1                     */
    const int8_t *n_plus;    /* rho x tau, 0/1                     */
    const int8_t *n_inhibit; /* rho x tau, 0/1, or NULL (none)     */
    const uint8_t *m0;       /* initial marking, rho entries       */
    int n_invariants;
    const int8_t *invariants; /* n_invariants x rho, or NULL        */
} petri_net;

/* Marking plus running set: the full discrete state. */
typedef struct {
    uint8_t m[PETRI_MAX_PLACES];
    uint32_t running; /* bit j: t_j started, not completed  */
} petri_state;

/* Per-net data derived once from the tables. */
typedef struct {
    const petri_net *net;
    int n_in[PETRI_MAX_TRANSITIONS]; /* I_j of the seed        */
    uint32_t in_mask[PETRI_MAX_TRANSITIONS];
    uint32_t out_mask[PETRI_MAX_TRANSITIONS]; /* places of N+_j    */
    uint32_t inhibit_mask[PETRI_MAX_TRANSITIONS];
    /* bit k: t_k's enabling can change when t_j starts or completes (an
     * input or inhibitor arc of t_k on a place of t_j's, or k = j) */
    uint32_t touch[PETRI_MAX_TRANSITIONS];
    int inv_value[PETRI_MAX_INVARIANTS]; /* y^T gamma0             */
    /* y_k^T N-_j (the tokens of t_j in flight) and y_k^T (N+_j - N-_j)
     * (what completing t_j adds to y_k^T gamma) */
    int16_t inv_in[PETRI_MAX_INVARIANTS][PETRI_MAX_TRANSITIONS];
    int16_t inv_step[PETRI_MAX_INVARIANTS][PETRI_MAX_TRANSITIONS];
} petri_compiled;

/* Validates sizes and 0/1 entries. Returns 0 or PETRI_ERR_ARG. */
int petri_compile(petri_compiled *c, const petri_net *net);
/* The whole definition is sound: what petri_compile checks, and every
 * transition can act (has an arc, is not inhibited by its own input), and
 * every invariant y is non-zero with y^T N = 0 for the incidence matrix
 * N = N+ - N- (so y^T gamma is conserved by every firing). Returns 0 or
 * the first PETRI_ERR_* found. For start-up checks of a const net. */
int petri_net_validate(const petri_net *net);
void petri_state_initial(const petri_compiled *c, petri_state *s);

/* Enabling (not running, inputs marked, inhibitor places empty):
 * the seed's algorithm (I_j, C_j counted with early stop) ... */
int petri_state_enabled_scan(const petri_compiled *c, const petri_state *s, int t);
/* ... and the equivalent bitmask test. Both return 1 / 0 (0 for bad t). */
int petri_state_enabled_mask(const petri_compiled *c, const petri_state *s, int t);
/* Number of invariants violated in s (running tokens counted in flight). */
int petri_state_invariant_violations(const petri_compiled *c, const petri_state *s);
/* Dead: no transition enabled and none running. */
int petri_state_dead(const petri_compiled *c, const petri_state *s);

/* ---- engine -----------------------------------------------------------
 * The engine keeps, besides the state, what its queries need, updated
 * after each start or completion instead of scanned for: the marked
 * places, the enabled transitions (only those in touch[t] re-checked)
 * and each invariant's y^T gamma + in-flight tokens (plus inv_step[t] on
 * completing t; a start leaves it unchanged). st is read-only to callers:
 * petri_set_state or petri_load_state change it. */
typedef struct {
    petri_compiled c;
    petri_state st;
    uint32_t marked;                   /* bit i: st.m[i] > 0                      */
    uint32_t enabled;                  /* bit j: t_j enabled in st                */
    int inv_now[PETRI_MAX_INVARIANTS]; /* y_k^T gamma + in flight        */
    long invariant_violations;         /* changes after which an invariant failed */
    int last_fired;                    /* last completed transition, -1 if none   */
    long fired_count;                  /* completions                             */
} petri;

int petri_init(petri *p, const petri_net *net);
/* Seed's event-path planning: lowest-index enabled transition,
 * PETRI_ERR_NONE_ENABLED if none. */
int petri_select(const petri *p);
int petri_enabled(const petri *p, int t);
int petri_running(const petri *p, int t);
int petri_start(petri *p, int t);
int petri_complete(petri *p, int t);
int petri_fire(petri *p, int t);
int petri_dead(const petri *p);
int petri_invariants_hold(const petri *p);
/* Takes a saved state back (a supervisor's journal after a restart): only
 * running bits of existing transitions and a marking that keeps every
 * P-invariant (tokens of running transitions counted). 0 or PETRI_ERR_ARG,
 * and then the state is unchanged. */
int petri_set_state(petri *p, const petri_state *s);
/* Takes s as it is (an explorer's state, which may break an invariant of
 * a faulty net: the checks then count it), its sets derived afresh. 0, or
 * PETRI_ERR_ARG (NULL, or running bits of no transition). */
int petri_load_state(petri *p, const petri_state *s);

/* ---- reachability ------------------------------------------------------ */
/* Workspace (large: make it static). BFS over states = marking + running
 * set, with "start t" and "complete t" as separate events; states[] is
 * the visited set and the BFS queue at once. */
typedef struct {
    petri_compiled c;
    petri_state states[PETRI_MAX_STATES];
    int16_t parent[PETRI_MAX_STATES]; /* predecessor index, -1 at root  */
    int8_t event[PETRI_MAX_STATES];   /* +(t+1) start, -(t+1) complete   */
    int16_t hash[PETRI_HASH_SIZE];    /* index + 1, 0 = empty           */
    int n_states;
} petri_explore_ws;

typedef struct {
    int n_states;
    int complete;         /* 1: whole reachable set fitted the capacity */
    int safe;             /* every place <= 1 in every visited state     */
    int bounded;          /* no place exceeded token_bound               */
    int deadlock;         /* a dead state is reachable                   */
    int invariant_states; /* visited states violating some invariant     */
    int max_tokens;
    /* first offending states (index into ws->states, -1 if none) */
    int unsafe_index, unbounded_index, dead_index, invariant_index;
} petri_report;

/* token_bound in 1..PETRI_TOKEN_MAX-1: a state with a place above it is
 * reported unbounded and not expanded. Returns 0 or PETRI_ERR_ARG (bad
 * net/args). */
int petri_explore(petri_explore_ws *ws, const petri_net *net, int token_bound, petri_report *rep);

/* Event path from the initial state to ws->states[index], as signed
 * events (+(t+1) start, -(t+1) complete), at most max entries, in order.
 * Returns the number written, or PETRI_ERR_ARG (also when it needs more
 * than max). */
int petri_explore_trace(const petri_explore_ws *ws, int index, int8_t *events, int max);

#endif

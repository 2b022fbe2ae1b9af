/* The one walk of the wide BVH (shared/bvh.h) that every ray kernel runs (ray_trace.cl's
   packets, ray_trace_single.cl, ray_query.cl), after Embree's traverser templates: the node
   layout's details (the wide node fetch, the children's order, the stack's entries, push and
   pop, entering a top-level leaf's instances, shared/instance.h) live here once, and what a
   kernel tests is its parameters. A kernel defines, before including this header:
     CLVIS_WALK_CTX                             its context type (what its tests read and update)
     CLVIS_WALK_CHILDREN(ctx, v, nd, xi, keys)  the node test: bit k set when child k of node nd
                                                (instance xi) is entered; keys[k] its order
                                                (nearest first) and the key its entry is pushed with
     CLVIS_WALK_KEY_SKIP(ctx, v, key)           a popped entry (instances included) is dropped
     CLVIS_WALK_BOX_SKIP(ctx, v, nd, k, xi)     a popped child is dropped (its box tested again)
     CLVIS_WALK_LEAF(ctx, v, tris, first, count, xi)  the leaf test of triangles tris[first ..
                                                first + count - 1]; nonzero ends the walk (any hit)
   and CLVIS_RAY_STACK (entries: each visit pushes at most CLVIS_BVH_WIDTH - 1, a top-level leaf
   at most its instances less one more). `v`
   is clvis_walk_step's `variant`, a constant the kernel picks its tests by (ray_trace.cl walks
   a packet two ways); `two_level` (a constant too) compiles the instance handling in or out.
   Always inlined with constant arguments, so each kernel gets its own walk's code. */
#ifndef CLVIS_SHARED_BVH_WALK_H
#define CLVIS_SHARED_BVH_WALK_H

#include "shared/bvh.h"
#include "shared/instance.h"

#if !defined(CLVIS_WALK_CTX) || !defined(CLVIS_WALK_CHILDREN) || !defined(CLVIS_WALK_KEY_SKIP) || \
    !defined(CLVIS_WALK_BOX_SKIP) || !defined(CLVIS_WALK_LEAF)
#error "define the walk's parameters (CLVIS_WALK_*) before including shared/bvh_walk.h"
#endif
#ifndef CLVIS_RAY_STACK
#error "CLVIS_RAY_STACK must be defined"
#endif

/* No node left to visit: the walk is over. */
#define CLVIS_WALK_DONE 0xFFFFFFFFu

/* A stack entry names a child slot, (wide node << CLVIS_BVH_SLOT_BITS) | slot, so that a popped
   child can be tested again against what the walk found since it was pushed. */
#define CLVIS_WALK_ENTRY(node, slot) ((clvis_u32)(node) << CLVIS_BVH_SLOT_BITS | (clvis_u32)(slot))
#define CLVIS_WALK_NODE(e) ((e) >> CLVIS_BVH_SLOT_BITS)
#define CLVIS_WALK_SLOT(e) ((int)((e) & (clvis_u32)(CLVIS_BVH_WIDTH - 1)))

/* The levels a two-level walk is in: the flat tree of a scene without instances (and the plain
   meshes' tree), the top level, whose leaves list instances, or instance i's tree. */
#define CLVIS_INST_FLAT 0xFFFFFFFFu
#define CLVIS_INST_TOP 0xFFFFFFFEu

/* A stack entry that enters the instance stored beside it. */
#define CLVIS_ENTER_INSTANCE 0xFFFFFFFFu

/* Where a walk stands between two steps. */
typedef struct clvis_walk {
    clvis_u32 node;                        /* the wide node visited next, or CLVIS_WALK_DONE */
    clvis_u32 sp;                          /* stack entries */
    clvis_u32 inst;                        /* two-level: the level (CLVIS_INST_*, or an instance) */
    CLVIS_GLOBAL const clvis_instance* xi; /* two-level: instance `inst`'s record, or none */
} clvis_walk;

/* The stack: entries, the key each was pushed with, and (two-level) the level it lies in. */
typedef struct clvis_walk_stack {
    clvis_u32 entry[CLVIS_RAY_STACK];
    float key[CLVIS_RAY_STACK];
    clvis_u32 inst[CLVIS_RAY_STACK];
} clvis_walk_stack;

/* Starts a walk at the root (none when the tree is empty), in the top level when `top`. */
static inline void clvis_walk_start(clvis_walk* w, clvis_u32 node_count, int top)
{
    w->node = node_count > 0 ? 0u : CLVIS_WALK_DONE;
    w->sp = 0;
    w->inst = top ? CLVIS_INST_TOP : CLVIS_INST_FLAT;
    w->xi = 0;
}

/* CLVIS_PREFETCH (PoCL's CPU device, Device::Impl::cpu_hints): a walk fetches every child it
   meets (the one visited next and those pushed) into the cache as the node is visited, so that
   the (up to CLVIS_BVH_WIDTH) misses of one node's children overlap instead of each stalling the walk when
   it is reached. A hint only: the walk reads the same values with or without it. */
static inline void clvis_prefetch_child(CLVIS_GLOBAL const clvis_wide_node* nodes,
                                        CLVIS_GLOBAL const clvis_bvh_tri* tris, CLVIS_GLOBAL const clvis_wide_node* n,
                                        int k)
{
#ifdef CLVIS_PREFETCH
    /* a node's cache lines, or a leaf's first two of triangles (past the end: no fault) */
    if (n->count[k] == 0) {
        CLVIS_GLOBAL const char* p = (CLVIS_GLOBAL const char*)(nodes + n->child[k]);
        /* unrolled: PoCL's compiler kept the loop over the lines, 4 instructions a line */
#ifdef __OPENCL_C_VERSION__
#pragma unroll
#endif
        for (int line = 0; line < (int)sizeof(clvis_wide_node); line += 64) CLVIS_PREFETCH_LINE(p + line);
    } else {
        CLVIS_GLOBAL const char* p = (CLVIS_GLOBAL const char*)(tris + n->child[k]);
        CLVIS_PREFETCH_LINE(p);
        CLVIS_PREFETCH_LINE(p + 64);
    }
#else
    (void)nodes; (void)tris; (void)n; (void)k;
#endif
}

/* Enters top-level entry j: instance j, or the plain meshes' tree (walked as the flat tree, no
   record). Returns the tree's root node. */
static inline clvis_u32 clvis_enter_instance(CLVIS_GLOBAL const clvis_instance* instances, clvis_u32 j, clvis_walk* w)
{
    clvis_u32 tree = instances[j].tree;
    int plain = (tree & CLVIS_INSTANCE_PLAIN) != 0u;
    w->inst = plain ? CLVIS_INST_FLAT : j;
    w->xi = plain ? 0 : instances + j;
    return tree & ~CLVIS_INSTANCE_PLAIN;
}

/* One step: visits w->node (the children its test passes, the nearest taken at once, the others
   pushed far to near), then takes children (popped ones that their tests keep) until the next
   node: a leaf's triangles are tested on the way, a top-level leaf enters its instances (the first
   at once, the others pushed with the leaf's key). w->node is CLVIS_WALK_DONE once the stack is
   empty or the leaf test ends the walk. A kernel steps until done, or interleaves the steps of
   several walks (ray_query.cl's lanes). */
static inline CLVIS_ALWAYS_INLINE void clvis_walk_step(CLVIS_WALK_CTX* ctx, const int variant, const int two_level,
                                                       CLVIS_GLOBAL const clvis_wide_node* nodes,
                                                       CLVIS_GLOBAL const clvis_bvh_tri* tris,
                                                       CLVIS_GLOBAL const clvis_instance* instances, clvis_walk* w,
                                                       clvis_walk_stack* st)
{
    (void)variant; /* for the parameters that ignore it */
    CLVIS_GLOBAL const clvis_wide_node* nd = nodes + w->node;
    CLVIS_GLOBAL const clvis_instance* xi = two_level ? w->xi : 0;
    float keys[CLVIS_BVH_WIDTH];
    int bits = CLVIS_WALK_CHILDREN(ctx, variant, nd, xi, keys);
    /* The nearest child met (by key; the first slot among equals) is visited next without a trip
       through the stack; the others are pushed far to near, so that the nearest pops first. The
       loop is unrolled, so that keys and the child at hand stay in registers. */
    int prefetch = !two_level || w->inst != CLVIS_INST_TOP; /* a top-level leaf lists instances */
    clvis_u32 base = w->sp, sp = w->sp;
    int k = -1;
    float key = 0.0f;
#ifdef __OPENCL_C_VERSION__
#pragma unroll
#endif
    for (int c = 0; c < CLVIS_BVH_WIDTH; ++c) {
        if (!(bits & (1 << c))) continue;
        if (prefetch) clvis_prefetch_child(nodes, tris, nd, c);
        if (k < 0) {
            k = c;
            key = keys[c];
            continue;
        }
        int push = c;
        float push_key = keys[c];
        if (push_key < key) {
            push = k;
            push_key = key;
            k = c;
            key = keys[c];
        }
        clvis_u32 i = sp++;
        for (; i > base && st->key[i - 1] < push_key; --i) {
            st->entry[i] = st->entry[i - 1];
            st->key[i] = st->key[i - 1];
        }
        st->entry[i] = CLVIS_WALK_ENTRY(nd - nodes, push);
        st->key[i] = push_key;
    }
    if (two_level)
        for (clvis_u32 i = base; i < sp; ++i) st->inst[i] = w->inst; /* all of this node */
    w->node = CLVIS_WALK_DONE;
    /* the child at hand: slot k of nd, met at key */
    int at_hand = k >= 0;
    for (;;) {
        if (!at_hand) {
            if (sp == 0) break;
            clvis_u32 e = st->entry[--sp];
            key = st->key[sp];
            if (two_level) {
                w->inst = st->inst[sp];
                xi = w->inst < CLVIS_INST_TOP ? instances + w->inst : 0;
                w->xi = xi;
            }
            if (CLVIS_WALK_KEY_SKIP(ctx, variant, key)) continue;
            if (two_level && e == CLVIS_ENTER_INSTANCE) {
                w->node = clvis_enter_instance(instances, w->inst, w);
                break;
            }
            nd = nodes + CLVIS_WALK_NODE(e);
            k = CLVIS_WALK_SLOT(e);
            if (CLVIS_WALK_BOX_SKIP(ctx, variant, nd, k, xi)) continue;
        }
        at_hand = 0;
        clvis_u32 first = nd->child[k], count = nd->count[k];
        if (count == 0) {
            w->node = first;
            break;
        }
        if (two_level && w->inst == CLVIS_INST_TOP) {
            /* entries first .. first + count - 1 of the instances: the first now, the others
               pushed beside their index */
            for (clvis_u32 j = count - 1; j > 0; --j, ++sp) {
                st->entry[sp] = CLVIS_ENTER_INSTANCE;
                st->key[sp] = key;
                st->inst[sp] = first + j;
            }
            w->node = clvis_enter_instance(instances, first, w);
            break;
        }
        if (CLVIS_WALK_LEAF(ctx, variant, tris, first, count, xi)) break; /* answered: node stays done */
    }
    w->sp = sp;
}

#endif

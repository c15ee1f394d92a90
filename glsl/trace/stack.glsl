// The stack of a mesh traversal (trace/bvh.glsl trace_mesh): MESH_STACK entries, as many
// as the scene's deepest hierarchy has levels (facet.render.rays.pack stack_entries), so an
// ordered traversal, which holds at most one waiting child per level, never drops one.
//
// Up to 32 entries the stack is held in variables, s00 on top, that all shift by one on a
// push and on a pop. An array indexed by a stack pointer differs per lane, and llvmpipe
// writes such an index one lane at a time, a load and a store each whether or not the lane
// pushes: the pushes were a fifth of a primary ray's time on the bunny (perf). Shifting
// 8 to 32 variables is as many vector selects, none per lane (primary rays 15-20% faster;
// docs/performance.md). A deeper hierarchy keeps the array. STACK_DECLARE, then
// STACK_PUSH(x) and STACK_POP(x) (-1 when empty); each written out, not looped: an
// array shifted in a loop that the compiler does not unroll is indexed per lane again.
#ifndef MESH_STACK
#error the stack's depth is facet.render.rays.pack's (stack_entries)
#endif

#if MESH_STACK > 32
#define STACK_DECLARE int stack_[MESH_STACK]; int sp_ = 0;
#define STACK_PUSH(x) { if (sp_ < MESH_STACK) stack_[sp_++] = (x); }
#define STACK_POP(x) { x = sp_ > 0 ? stack_[--sp_] : -1; }
#else

#define STACK_DECLARE_0 int s00 = -1, s01 = -1, s02 = -1, s03 = -1, s04 = -1, s05 = -1, \
                            s06 = -1, s07 = -1;
#define STACK_PUSH_0 s07 = s06; s06 = s05; s05 = s04; s04 = s03; s03 = s02; s02 = s01; \
                     s01 = s00;
#define STACK_POP_0 s00 = s01; s01 = s02; s02 = s03; s03 = s04; s04 = s05; s05 = s06; \
                    s06 = s07;
#if MESH_STACK > 8
#define STACK_DECLARE_1 int s08 = -1, s09 = -1, s10 = -1, s11 = -1, s12 = -1, s13 = -1, \
                            s14 = -1, s15 = -1;
#define STACK_PUSH_1 s15 = s14; s14 = s13; s13 = s12; s12 = s11; s11 = s10; s10 = s09; \
                     s09 = s08; s08 = s07;
#define STACK_POP_1 s07 = s08; s08 = s09; s09 = s10; s10 = s11; s11 = s12; s12 = s13; \
                    s13 = s14; s14 = s15;
#else
#define STACK_DECLARE_1
#define STACK_PUSH_1
#define STACK_POP_1
#endif
#if MESH_STACK > 16
#define STACK_DECLARE_2 int s16 = -1, s17 = -1, s18 = -1, s19 = -1, s20 = -1, s21 = -1, \
                            s22 = -1, s23 = -1;
#define STACK_PUSH_2 s23 = s22; s22 = s21; s21 = s20; s20 = s19; s19 = s18; s18 = s17; \
                     s17 = s16; s16 = s15;
#define STACK_POP_2 s15 = s16; s16 = s17; s17 = s18; s18 = s19; s19 = s20; s20 = s21; \
                    s21 = s22; s22 = s23;
#else
#define STACK_DECLARE_2
#define STACK_PUSH_2
#define STACK_POP_2
#endif
#if MESH_STACK > 24
#define STACK_DECLARE_3 int s24 = -1, s25 = -1, s26 = -1, s27 = -1, s28 = -1, s29 = -1, \
                            s30 = -1, s31 = -1;
#define STACK_PUSH_3 s31 = s30; s30 = s29; s29 = s28; s28 = s27; s27 = s26; s26 = s25; \
                     s25 = s24; s24 = s23;
#define STACK_POP_3 s23 = s24; s24 = s25; s25 = s26; s26 = s27; s27 = s28; s28 = s29; \
                    s29 = s30; s30 = s31;
#define STACK_BOTTOM s31
#elif MESH_STACK > 16
#define STACK_DECLARE_3
#define STACK_PUSH_3
#define STACK_POP_3
#define STACK_BOTTOM s23
#elif MESH_STACK > 8
#define STACK_DECLARE_3
#define STACK_PUSH_3
#define STACK_POP_3
#define STACK_BOTTOM s15
#else
#define STACK_DECLARE_3
#define STACK_PUSH_3
#define STACK_POP_3
#define STACK_BOTTOM s07
#endif

#define STACK_DECLARE STACK_DECLARE_0 STACK_DECLARE_1 STACK_DECLARE_2 STACK_DECLARE_3
#define STACK_PUSH(x) { STACK_PUSH_3 STACK_PUSH_2 STACK_PUSH_1 STACK_PUSH_0 s00 = (x); }
#define STACK_POP(x) { x = s00; STACK_POP_0 STACK_POP_1 STACK_POP_2 STACK_POP_3 \
                       STACK_BOTTOM = -1; }
#endif

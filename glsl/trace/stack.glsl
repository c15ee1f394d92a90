// The stacks of the traversals: a mesh's (trace/bvh.glsl trace_mesh, MESH_STACK entries:
// the scene's deepest hierarchy's levels less two, since an ordered traversal holds at most
// one waiting child per level and trace_mesh pushes none where a child is a leaf) and the
// top level's (trace/scene.glsl WALK, TOP_STACK: one more than the placed objects).
// facet.render.rays.pack stack_defines sets both.
//
// Up to 32 entries a stack is held in variables, s00 on top, that all shift by one on a
// push and on a pop (REGISTER_STACK of them: the larger of the two stacks held so). An
// array indexed by a stack pointer differs per lane, and llvmpipe writes such an index one
// lane at a time, a load and a store each whether or not the lane pushes: the pushes were
// a fifth of a primary ray's time on the bunny (perf). Shifting 8 to 32 variables is as
// many vector selects, none per lane (primary rays 25-35% faster; docs/performance.md).
// A larger stack is an array. Each written out, not looped: an array shifted in a loop
// that the compiler does not unroll is indexed per lane again.
// <KIND>_DECLARE, <KIND>_PUSH(x), <KIND>_POP(x) (STACK_NONE when empty), <KIND>_EMPTY for
// KIND = MESH_STACK and TOP_STACK; entries are ints other than STACK_NONE.
#if !defined(MESH_STACK) || !defined(TOP_STACK) || !defined(REGISTER_STACK)
#error the stacks' depths are facet.render.rays.pack's (stack_defines)
#endif
const int STACK_NONE = -2147483647 - 1;

#define ARRAY_DECLARE(n) int stack_[n]; int sp_ = 0;
#define ARRAY_PUSH(n, x) { if (sp_ < (n)) stack_[sp_++] = (x); }
#define ARRAY_POP(x) { x = sp_ > 0 ? stack_[--sp_] : STACK_NONE; }
#define ARRAY_EMPTY (sp_ == 0)

#define STACK_DECLARE_0 int s00, s01, s02, s03, \
                            s04, s05, s06, s07; \
    s00 = s01 = s02 = s03 = s04 = s05 = s06 = s07 = STACK_NONE;
#define STACK_PUSH_0 s07 = s06; s06 = s05; s05 = s04; s04 = s03; s03 = s02; s02 = s01; \
                     s01 = s00;
#define STACK_POP_0 s00 = s01; s01 = s02; s02 = s03; s03 = s04; s04 = s05; s05 = s06; \
                    s06 = s07;
#if REGISTER_STACK > 8
#define STACK_DECLARE_1 int s08, s09, s10, s11, \
                            s12, s13, s14, s15; \
    s08 = s09 = s10 = s11 = s12 = s13 = s14 = s15 = STACK_NONE;
#define STACK_PUSH_1 s15 = s14; s14 = s13; s13 = s12; s12 = s11; s11 = s10; s10 = s09; \
                     s09 = s08; s08 = s07;
#define STACK_POP_1 s07 = s08; s08 = s09; s09 = s10; s10 = s11; s11 = s12; s12 = s13; \
                    s13 = s14; s14 = s15;
#else
#define STACK_DECLARE_1
#define STACK_PUSH_1
#define STACK_POP_1
#endif
#if REGISTER_STACK > 16
#define STACK_DECLARE_2 int s16, s17, s18, s19, \
                            s20, s21, s22, s23; \
    s16 = s17 = s18 = s19 = s20 = s21 = s22 = s23 = STACK_NONE;
#define STACK_PUSH_2 s23 = s22; s22 = s21; s21 = s20; s20 = s19; s19 = s18; s18 = s17; \
                     s17 = s16; s16 = s15;
#define STACK_POP_2 s15 = s16; s16 = s17; s17 = s18; s18 = s19; s19 = s20; s20 = s21; \
                    s21 = s22; s22 = s23;
#else
#define STACK_DECLARE_2
#define STACK_PUSH_2
#define STACK_POP_2
#endif
#if REGISTER_STACK > 24
#define STACK_DECLARE_3 int s24, s25, s26, s27, \
                            s28, s29, s30, s31; \
    s24 = s25 = s26 = s27 = s28 = s29 = s30 = s31 = STACK_NONE;
#define STACK_PUSH_3 s31 = s30; s30 = s29; s29 = s28; s28 = s27; s27 = s26; s26 = s25; \
                     s25 = s24; s24 = s23;
#define STACK_POP_3 s23 = s24; s24 = s25; s25 = s26; s26 = s27; s27 = s28; s28 = s29; \
                    s29 = s30; s30 = s31;
#define STACK_BOTTOM s31
#elif REGISTER_STACK > 16
#define STACK_DECLARE_3
#define STACK_PUSH_3
#define STACK_POP_3
#define STACK_BOTTOM s23
#elif REGISTER_STACK > 8
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

#define REGISTER_DECLARE STACK_DECLARE_0 STACK_DECLARE_1 STACK_DECLARE_2 STACK_DECLARE_3
#define REGISTER_PUSH(x) { STACK_PUSH_3 STACK_PUSH_2 STACK_PUSH_1 STACK_PUSH_0 s00 = (x); }
#define REGISTER_POP(x) { x = s00; STACK_POP_0 STACK_POP_1 STACK_POP_2 STACK_POP_3 \
                       STACK_BOTTOM = STACK_NONE; }
#define REGISTER_EMPTY (s00 == STACK_NONE)

#if MESH_STACK <= 32
#define MESH_STACK_DECLARE REGISTER_DECLARE
#define MESH_STACK_PUSH(x) REGISTER_PUSH(x)
#define MESH_STACK_POP(x) REGISTER_POP(x)
#else
#define MESH_STACK_DECLARE ARRAY_DECLARE(MESH_STACK)
#define MESH_STACK_PUSH(x) ARRAY_PUSH(MESH_STACK, x)
#define MESH_STACK_POP(x) ARRAY_POP(x)
#endif
#if TOP_STACK <= 32
#define TOP_STACK_DECLARE REGISTER_DECLARE
#define TOP_STACK_PUSH(x) REGISTER_PUSH(x)
#define TOP_STACK_POP(x) REGISTER_POP(x)
#define TOP_STACK_EMPTY REGISTER_EMPTY
#else
#define TOP_STACK_DECLARE ARRAY_DECLARE(TOP_STACK)
#define TOP_STACK_PUSH(x) ARRAY_PUSH(TOP_STACK, x)
#define TOP_STACK_POP(x) ARRAY_POP(x)
#define TOP_STACK_EMPTY ARRAY_EMPTY
#endif

// render/shaders/stack_ladder.glsl - the walk's stack as a ladder of selects
// (STK_PUT(S, V): stk_node[S] = V; STK_GET(S, OUT): OUT = uint(stk_node[S])),
// one definition for the two walks that use it on CPU devices: trace.comp's
// (trace_common.glsl, TRACE_STACK_SELECTS, STK_REG) and the compact kernel's
// (trace_compact.comp, LADDER). Every access to stk_node is then at a constant
// index, so lavapipe keeps the array in registers instead of writing and
// reading it lane by lane (the reasons and numbers stand at each includer).
//
// The includer declares int stk_node[] (at least S_MAX slots) in the walk and
// const int STK_LO, the lowest slot the kernel's walk pushes at (a
// specialisation constant: an entry below it is left out when the kernel is
// specialised). Before the #include it may define
//   STK_LADDER_DEEP: its walk can push below slot 14 (models past 10 levels:
//     trace.comp's DEEP 2, slots 3 up); without it the ladder starts at 14;
//   STK_LADDER_GUARD_ALL: slots 16 and up are guarded by STK_LO too (always
//     true: every walk pushes there; trace.comp keeps the guards).
// So each includer's SPIR-V is byte for byte what its own copy of the ladder
// compiled to (checked on all 20 render kernels and the probes', cones' and
// photons' 11), and sharing the text costs nothing anywhere.
//
// Why the two switches and not one text with every slot guarded (stop 48's
// attempt, after which test_compact_gpu took 416 s on lavapipe against
// 182 s): most of that was Mesa's shader cache, not the text. lavapipe
// compiles a kernel with LLVM at its first dispatch and keeps the result in
// ~/.cache/mesa_shader_cache; new SPIR-V compiles again (test_compact_gpu's
// test_deep: 43-46 s of CPU with an empty cache, 21-31 s with a warm one, the
// copy's text and the guarded text alike). Warm, the guarded text's longer
// SPIR-V (slots 3-13 translated and optimised before specialisation drops
// them) made vkCreateComputePipelines 1.01-1.24x as slow in three ABAB
// rounds: noise on this machine or a real cost, it is none with the switches
// (docs/PERFORMANCE.md, issue 18, branch debt).

#define STK_PG(k) if (k >= STK_LO) stk_node[k] = s_ == k ? v_ : stk_node[k];
#define STK_PU(k) stk_node[k] = s_ == k ? v_ : stk_node[k];
#define STK_GG(k) if (k >= STK_LO) g_ = s_ == k ? stk_node[k] : g_;
#define STK_GU(k) g_ = s_ == k ? stk_node[k] : g_;
#ifdef STK_LADDER_DEEP
#define STK_PUT_DEEP STK_PG(3) STK_PG(4) STK_PG(5) STK_PG(6) STK_PG(7) STK_PG(8) STK_PG(9) STK_PG(10) STK_PG(11) STK_PG(12) STK_PG(13)
#define STK_GET_DEEP STK_GG(3) STK_GG(4) STK_GG(5) STK_GG(6) STK_GG(7) STK_GG(8) STK_GG(9) STK_GG(10) STK_GG(11) STK_GG(12) STK_GG(13)
#else
#define STK_PUT_DEEP
#define STK_GET_DEEP
#endif
#ifdef STK_LADDER_GUARD_ALL
#define STK_PUT_TOP STK_PG(16) STK_PG(17) STK_PG(18) STK_PG(19) STK_PG(20) STK_PG(21) STK_PG(22)
#define STK_GET_TOP STK_GG(16) STK_GG(17) STK_GG(18) STK_GG(19) STK_GG(20) STK_GG(21)
#else
#define STK_PUT_TOP STK_PU(16) STK_PU(17) STK_PU(18) STK_PU(19) STK_PU(20) STK_PU(21) STK_PU(22)
#define STK_GET_TOP STK_GU(16) STK_GU(17) STK_GU(18) STK_GU(19) STK_GU(20) STK_GU(21)
#endif
#define STK_PUT(S, V) { int s_ = (S), v_ = (V); STK_PUT_DEEP STK_PG(14) STK_PG(15) STK_PUT_TOP }
#define STK_GET(S, OUT) { int s_ = (S), g_ = stk_node[S_MAX - 1]; STK_GET_DEEP STK_GG(14) STK_GG(15) STK_GET_TOP OUT = uint(g_); }

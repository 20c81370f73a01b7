// alpha_test.glsl: the one alpha test of fovsim (STYLE.md: "Put the alpha test in one function").
// C twin: alpha_test_passes() in src/passes/alpha_test.c. The chosen strategy comes from the plan as
// ALPHA_MODE (an ALPHA_MODE_ID_* value from shared_defs.h).
#ifndef ALPHA_MODE
#error "alpha_test.glsl needs ALPHA_MODE (set by the plan)"
#endif

// True when a fragment of opacity `alpha` survives. Traditional: alpha >= cutoff
// (glTF MASK semantics: "rendered fully opaque if alpha >= alphaCutoff").
bool alpha_test_passes(float alpha, float cutoff)
{
#if ALPHA_MODE == ALPHA_MODE_ID_TRADITIONAL
    return alpha >= cutoff;
#else
#error "this ALPHA_MODE is not implemented yet"
#endif
}

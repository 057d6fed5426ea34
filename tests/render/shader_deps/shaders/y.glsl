// included by x.glsl (so a.comp through it) and by b.comp where WITH_Y is defined
float y_val() { return 2.0; }

/* The sRGB transfer function (IEC 61966-2-1). */
#ifndef PB_CORE_SRGB_H
#define PB_CORE_SRGB_H

/* sRGB-encoded value to linear. */
float pb_srgb_to_linear(float v);
/* Linear value to sRGB-encoded; 0 for values <= 0 and NaN. */
float pb_linear_to_srgb(float v);

#endif

/* Constants of the Principled v2 thin-film iridescence as Cycles 4.5
 * computes it (src/kernel/closure/bsdf_util.h iridescence_lookup_sensitivity
 * and fresnel_iridescence): Belcour and Barla 2017's Gaussian fit of the CIE
 * 1931 XYZ sensitivities in Fourier space, and the XYZ to scene-linear
 * Rec.709 conversion Cycles applies after multiplying by the working space's
 * white point (Cycles' film white_xyz and xyz_to_r/g/b: Blender's default
 * Linear Rec.709, D65). Figures only: the reference (src/ref/principled.c)
 * and the GPU (shaders/common/principled.glsl) each compute the model with
 * their own code. Plain decimal literals, valid in C and GLSL. */
#ifndef PB_THIN_FILM_H
#define PB_THIN_FILM_H

/* Cycles applies the film where its thickness is above this (nm), and
 * blends the film's IOR towards the outside medium's below 30 nm. */
#define PB_TF_MIN_THICKNESS 0.1
#define PB_TF_BLEND_THICKNESS 30.0

/* Gaussian fit per XYZ component: val, pos, var (phase in rad/m), and the
 * extra lobe on X; normalised by PB_TF_NORM. */
#define PB_TF_VAL_X 5.4856e-13
#define PB_TF_VAL_Y 4.4201e-13
#define PB_TF_VAL_Z 5.2481e-13
#define PB_TF_POS_X 1.6810e+06
#define PB_TF_POS_Y 1.7953e+06
#define PB_TF_POS_Z 2.2084e+06
#define PB_TF_VAR_X 4.3278e+09
#define PB_TF_VAR_Y 9.3046e+09
#define PB_TF_VAR_Z 6.6121e+09
#define PB_TF_X2_AMP 1.64408e-8
#define PB_TF_X2_POS 2.2399e+06
#define PB_TF_X2_VAR 4.5282e+09
#define PB_TF_NORM 1.0685e-7

/* The working space's white in XYZ (D65) and XYZ to linear Rec.709, rows. */
#define PB_TF_WHITE_X 0.950456
#define PB_TF_WHITE_Y 1.0
#define PB_TF_WHITE_Z 1.088754
#define PB_TF_M00 3.2404542
#define PB_TF_M01 -1.5371385
#define PB_TF_M02 -0.4985314
#define PB_TF_M10 -0.9692660
#define PB_TF_M11 1.8760108
#define PB_TF_M12 0.0415560
#define PB_TF_M20 0.0556434
#define PB_TF_M21 -0.2040259
#define PB_TF_M22 1.0572252

#endif

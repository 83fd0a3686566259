/* meristem — the Populus deltoides (eastern cottonwood) of G04 §5, grown over 27
 * years, as a definition of the inverse model. G04 does not print its functions;
 * these are drawn from its text (§2.2, §4) and figures (Figs. 8–11, 14–15):
 *   G_h   fast height growth that slows with age (a broom stick first);
 *   G_s1  the young silhouette: short branches all along the trunk (the broom);
 *   G_s2  the mature silhouette: longest branches a third of the way up, a
 *         rounded crown (Fig. 8);
 *   G_o1  short branches turn steadily upward; G_o2  long ones first droop below
 *         their original heading, then turn up at the tip: the S curve (Fig. 9);
 *   G_bs  branches low on their parent get a small scale factor, so they stay
 *         short (Fig. 10) and, by G_a, are shed first (Fig. 11);
 *   G_ss  the lateral nearest a shoot's tip is the longest; the lowest buds of a
 *         shoot make no branch (s_b < s_min; §2.2, Fig. 3);
 *   G_a   lifespan rising steeply with s_b: interior and lower branches go first;
 *   G_m   metamers by shoot length; G_l leaf size along the shoot (the only
 *         linear function here: a tent of three points);
 *   G_e, G_lg, G_bg  sigmoid growth of internode, leaf and bud (Figs. 12–13);
 *   G_r   the radius along a branch (§4.1): a flared base, then a taper.
 * Branching angles run from 80° (short) to 35° (long) as G04 §2.2 observes.
 *
 * Kept as .fset text, not a C table: the library reads no files, and this text is
 * what a client downloads, edits in the function editor and uploads again. */
#include "config.h"

#include <assert.h>
#include <string.h>

#include "models/inverse/inverse.h"

const char merp_inv_populus_fset[] =
    "funcgalleryver 1 1\n"
    "items: 14\n"
    "fver 1 1\n"
    "name: G_h\n"
    "samples: 64\n"
    "flip: off\n"
    "points: 4\n"
    "0 0.02\n"
    "0.3 0.45\n"
    "0.7 0.86\n"
    "1 1\n"
    "fver 1 1\n"
    "name: G_s1\n"
    "samples: 64\n"
    "flip: off\n"
    "points: 4\n"
    "0 0.12\n"
    "0.5 0.12\n"
    "0.9 0.04\n"
    "1 0\n"
    "fver 1 1\n"
    "name: G_s2\n"
    "samples: 64\n"
    "flip: off\n"
    "points: 5\n"
    "0 0.3\n"
    "0.3 0.6\n"
    "0.6 0.5\n"
    "0.85 0.25\n"
    "1 0\n"
    "fver 1 1\n"
    "name: G_o1\n"
    "samples: 64\n"
    "flip: off\n"
    "points: 4\n"
    "0 0\n"
    "0.3 0.1\n"
    "0.7 0.3\n"
    "1 0.5\n"
    "fver 1 1\n"
    "name: G_o2\n"
    "samples: 64\n"
    "flip: off\n"
    "points: 4\n"
    "0 -0.5\n"
    "0.3 -0.4\n"
    "0.7 0.2\n"
    "1 0.8\n"
    "fver 1 1\n"
    "name: G_bs\n"
    "samples: 64\n"
    "flip: off\n"
    "points: 4\n"
    "0 0.3\n"
    "0.3 0.9\n"
    "0.6 1\n"
    "1 0.55\n"
    "fver 1 1\n"
    "name: G_ss\n"
    "samples: 64\n"
    "flip: off\n"
    "points: 4\n"
    "0 0\n"
    "0.5 0.2\n"
    "0.8 0.7\n"
    "1 1\n"
    "fver 1 1\n"
    "name: G_a\n"
    "samples: 64\n"
    "flip: off\n"
    "points: 4\n"
    "0 0.05\n"
    "0.4 0.12\n"
    "0.8 0.45\n"
    "1 1\n"
    "fver 1 1\n"
    "name: G_m\n"
    "samples: 64\n"
    "flip: off\n"
    "points: 4\n"
    "0 0.1\n"
    "0.3 0.35\n"
    "0.7 0.75\n"
    "1 1\n"
    "fver 1 1\n"
    "name: G_l\n"
    "samples: 64\n"
    "flip: off\n"
    "kind: linear\n"
    "points: 3\n"
    "0 0.6\n"
    "0.5 1\n"
    "1 0.7\n"
    "fver 1 1\n"
    "name: G_e\n"
    "samples: 64\n"
    "flip: off\n"
    "points: 4\n"
    "0 0\n"
    "0.3 0.05\n"
    "0.7 0.95\n"
    "1 1\n"
    "fver 1 1\n"
    "name: G_lg\n"
    "samples: 64\n"
    "flip: off\n"
    "points: 4\n"
    "0 0\n"
    "0.2 0.1\n"
    "0.5 0.9\n"
    "1 1\n"
    "fver 1 1\n"
    "name: G_bg\n"
    "samples: 64\n"
    "flip: off\n"
    "points: 4\n"
    "0 0\n"
    "0.5 0\n"
    "0.8 0.6\n"
    "1 1\n"
    "fver 1 1\n"
    "name: G_r\n"
    "samples: 64\n"
    "flip: off\n"
    "points: 4\n"
    "0 1\n"
    "0.1 0.75\n"
    "0.6 0.45\n"
    "1 0.08\n";

mer_result merp_inv_populus(merp_inv_def *d, mer_error *err)
{
    assert(d != NULL);
    memset(d, 0, sizeof *d);
    d->y_max = 27;
    d->h_max = 20.0f; /* m: a 27-year cottonwood in the open */
    d->l_min = 0.05f;
    d->l_max = 8.0f;
    d->ls_max = 1.2f;
    d->m_max = 16;
    d->a_max = 24.0f;
    d->s_min = 0.25f;
    d->theta_max = 60.0f;
    d->beta_short = 80.0f;
    d->beta_long = 35.0f;
    d->leaf_size = 0.12f;
    d->span = 0.5f;
    d->order_max = 3;
    d->jitter = 6.0f;
    d->r_max = 0.3f; /* m: a trunk some 60 cm across at the base */
    mer_result rc = merp_inv_def_functions(d, merp_inv_populus_fset,
                                           sizeof merp_inv_populus_fset - 1, err);
    return rc == MER_OK ? merp_inv_def_check(d, err) : rc;
}

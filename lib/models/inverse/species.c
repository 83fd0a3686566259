/* meristem — two more inverse-model trees (G04 §4) that show the model's range
 * beside the Populus of G04 §5; G04 models only the Populus, so these are ours.
 * Each starts from the Populus and replaces some functions and scalars:
 *  - an excurrent conifer: steady height growth (G_h near linear), a cone for
 *    both silhouettes (longest branches at the base, none at the top), level
 *    branches (80–90°) that droop a little and lift their tips, laterals only
 *    near each shoot's tip (G_ss: tiers), and long-lived branches (G_a, a_max);
 *  - a weeping form: branches leave at 40–60° and then, by headings G_o1, G_o2
 *    that turn away from the parent all along, arch over and hang. */
#include "config.h"

#include <assert.h>

#include "models/inverse/inverse.h"

static const char conifer_fset[] =
    "funcgalleryver 1 1\n"
    "items: 8\n"
    "fver 1 1\n"
    "name: G_h\n"
    "samples: 64\n"
    "flip: off\n"
    "points: 4\n"
    "0 0.02\n"
    "0.3 0.3\n"
    "0.7 0.72\n"
    "1 1\n"
    "fver 1 1\n"
    "name: G_s1\n"
    "samples: 64\n"
    "flip: off\n"
    "points: 4\n"
    "0 0.3\n"
    "0.3 0.22\n"
    "0.7 0.1\n"
    "1 0\n"
    "fver 1 1\n"
    "name: G_s2\n"
    "samples: 64\n"
    "flip: off\n"
    "points: 4\n"
    "0 0.35\n"
    "0.3 0.25\n"
    "0.7 0.1\n"
    "1 0\n"
    "fver 1 1\n"
    "name: G_o1\n"
    "samples: 64\n"
    "flip: off\n"
    "kind: linear\n"
    "points: 2\n"
    "0 0.05\n"
    "1 0.15\n"
    "fver 1 1\n"
    "name: G_o2\n"
    "samples: 64\n"
    "flip: off\n"
    "points: 4\n"
    "0 -0.3\n"
    "0.5 -0.2\n"
    "0.8 0\n"
    "1 0.3\n"
    "fver 1 1\n"
    "name: G_bs\n"
    "samples: 64\n"
    "flip: off\n"
    "kind: linear\n"
    "points: 3\n"
    "0 0.8\n"
    "0.5 1\n"
    "1 1\n"
    "fver 1 1\n"
    "name: G_ss\n"
    "samples: 64\n"
    "flip: off\n"
    "points: 4\n"
    "0 0\n"
    "0.6 0\n"
    "0.85 0.5\n"
    "1 1\n"
    "fver 1 1\n"
    "name: G_a\n"
    "samples: 64\n"
    "flip: off\n"
    "kind: linear\n"
    "points: 3\n"
    "0 0.2\n"
    "0.5 0.6\n"
    "1 1\n";

static const char weeping_fset[] =
    "funcgalleryver 1 1\n"
    "items: 4\n"
    "fver 1 1\n"
    "name: G_h\n"
    "samples: 64\n"
    "flip: off\n"
    "points: 4\n"
    "0 0.03\n"
    "0.3 0.5\n"
    "0.7 0.88\n"
    "1 1\n"
    "fver 1 1\n"
    "name: G_s2\n"
    "samples: 64\n"
    "flip: off\n"
    "points: 4\n"
    "0 0.3\n"
    "0.3 0.6\n"
    "0.7 0.55\n"
    "1 0.1\n"
    "fver 1 1\n"
    "name: G_o1\n"
    "samples: 64\n"
    "flip: off\n"
    "kind: linear\n"
    "points: 3\n"
    "0 -0.1\n"
    "0.5 -0.5\n"
    "1 -0.8\n"
    "fver 1 1\n"
    "name: G_o2\n"
    "samples: 64\n"
    "flip: off\n"
    "points: 4\n"
    "0 -0.5\n"
    "0.3 -1\n"
    "0.7 -1\n"
    "1 -1\n";

mer_result merp_inv_conifer(merp_inv_def *d, mer_error *err)
{
    mer_result rc = merp_inv_populus(d, err);
    if (rc == MER_OK)
        rc = merp_inv_def_replace(d, conifer_fset, sizeof conifer_fset - 1, err);
    if (rc != MER_OK)
        return rc;
    d->h_max = 18.0f;
    d->l_max = 5.0f;
    d->a_max = 40.0f;
    d->s_min = 0.3f;
    d->beta_short = 88.0f;
    d->beta_long = 78.0f;
    d->order_max = 2;
    return merp_inv_def_check(d, err);
}

mer_result merp_inv_weeping(merp_inv_def *d, mer_error *err)
{
    mer_result rc = merp_inv_populus(d, err);
    if (rc == MER_OK)
        rc = merp_inv_def_replace(d, weeping_fset, sizeof weeping_fset - 1, err);
    if (rc != MER_OK)
        return rc;
    d->h_max = 12.0f;
    d->l_max = 6.0f;
    d->theta_max = 90.0f;
    d->beta_short = 60.0f;
    d->beta_long = 40.0f;
    return merp_inv_def_check(d, err);
}

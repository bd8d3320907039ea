"""The ROC/AUC code of python/rodend/analysis/detectability.py on synthetic data with a closed
form: two normal populations of equal std sigma whose means differ by dmu have
AUC = Phi(dmu / (sqrt(2) sigma)), and at 5 % false alarms a detection probability of
1 - Phi(z_0.95 - dmu/sigma). Also the limits: identical populations give 0.5, separated ones 1,
and a feature that falls with the clearance is oriented so that its AUC is above 0.5.

usage: test_detectability.py REPO
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(sys.argv[1], "python", "rodend", "analysis"))
import detectability as d  # noqa: E402


def phi(x):
    return 0.5 * (1 + math.erf(x / math.sqrt(2)))


def main():
    rng = np.random.default_rng(43)
    n = 4000
    for dmu in (0.0, 0.5, 1.0, 2.0):
        neg = rng.normal(0.0, 1.0, n)
        pos = rng.normal(dmu, 1.0, n)
        exact = phi(dmu / math.sqrt(2))
        # the AUC of n x n draws has std below sqrt(1/(12 n)) x 2 = 0.009 (Mann-Whitney):
        # 4 of those
        got = d.auc(neg, pos)
        assert abs(got - exact) < 0.02, (dmu, got, exact)
        # detection at 5 % false alarm: threshold z = 1.645; binomial std of n draws 0.008
        pd_exact = 1 - phi(1.6448536 - dmu)
        got_pd = d.detection_probability(neg, pos)
        assert abs(got_pd - pd_exact) < 0.04, (dmu, got_pd, pd_exact)
        # the ROC's trapezoid area is the AUC
        fa, pdet = d.roc(neg, pos)
        area = float(np.sum(np.diff(fa) * 0.5 * (pdet[1:] + pdet[:-1])))
        assert abs(area - got) < 1e-9, (area, got)
    # the bootstrap interval holds the closed form (at dmu = 1, n = 200)
    neg, pos = rng.normal(0, 1, 200), rng.normal(1, 1, 200)
    lo, hi = d.auc_interval(neg, pos, resamples=500)
    assert lo < phi(1 / math.sqrt(2)) < hi, (lo, hi)
    # limits: ties give 0.5, separated populations 1
    assert d.auc([1, 1, 1], [1, 1]) == 0.5
    assert d.auc([0, 1], [2, 3]) == 1.0
    # a falling feature, oriented
    worn = d.oriented(np.array([1.0, 2.0]), np.array([5.0, 6.0]))
    assert d.auc(-np.array([5.0, 6.0]), worn) == 1.0
    print("detectability ROC/AUC: ok")


if __name__ == "__main__":
    main()

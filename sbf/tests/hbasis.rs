//! H-basis identities.

use sbf::gram::gram_with_rule;
use sbf::quadrature::SphereQuadrature;
use sbf::{Basis, Domain, HBasis};

/// H-basis 4 and 6 are orthonormal on the upper hemisphere to 1e-8 (exact
/// rule for degree 4, so the residual is rounding).
#[test]
fn hbasis_orthonormal_on_hemisphere() {
    for n in [4, 6] {
        let h = HBasis::new(n).unwrap();
        assert_eq!(h.domain(), Domain::UpperHemisphere);
        let rule = SphereQuadrature::exact_for_degree(Domain::UpperHemisphere, 4);
        let g = gram_with_rule(&h, &rule);
        let err = (g - sbf::nalgebra::DMatrix::<f64>::identity(n, n)).abs().max();
        assert!(err < 1e-8, "H{n}: max |G − I| = {err:e}");
    }
    assert!(HBasis::new(5).is_err());
}

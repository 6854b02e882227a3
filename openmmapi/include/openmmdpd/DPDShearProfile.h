#ifndef OPENMMDPD_DPDSHEARPROFILE_H_
#define OPENMMDPD_DPDSHEARPROFILE_H_

#include "openmmdpd/DPDForcingProfile.h"
#include <complex>

namespace OpenMMDPD {

/**
 * Transverse forcing for the shear viscosity (Wu & Shang sec. 4.2.2): F_i = f(y_i) e_x with f
 * sinusoidal, piecewise linear or piecewise constant in y in [0, L_y), and the response the part of
 * the first Fourier mode of the velocity (eq. 89) that f excites:
 *     G_i = (1/(m_i N)) s(2 pi y_i / L_y) e_x,  s = sin for sinusoidal and piecewise constant, cos for piecewise linear.
 * The viscosity is nu = rho F_1 / U_1 (L_y / 2 pi)^2 (eq. 87) with F_1 known analytically
 * (getFirstFourierCoefficient) and U_1 the response per unit forcing.
 */
class DPDShearProfile : public DPDForcingProfile {
public:
    enum Shape { Sinusoidal = 0, PiecewiseLinear = 1, PiecewiseConstant = 2 };
    explicit DPDShearProfile(Shape shape) : shape(shape) {}
    static Shape shapeFromName(const std::string& name);
    static std::string shapeName(Shape shape);
    Shape getShape() const { return shape; }
    std::string getType() const override { return "Shear"; }
    std::unique_ptr<DPDForcingProfile> clone() const override { return std::make_unique<DPDShearProfile>(*this); }
    bool dependsOnPositions() const override { return true; }
    void evaluate(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box, const std::vector<double>& masses,
                  std::vector<OpenMM::Vec3>& force, std::vector<OpenMM::Vec3>& response) const override;
    /** f(y) for y in [0, L_y). */
    double profile(double y, double boxHeight) const;
    /** Every particle is forced: throws, naming the first, unless every mass is > 0. */
    void requirePositiveMasses(const std::vector<double>& masses) const;
    /**
     * The component of F_1 = (1/L_y) int f(y) exp(2 i pi y / L_y) dy (eq. 88) that the response
     * measures: Im F_1 = 1/2 (sinusoidal), 2/pi (piecewise constant); Re F_1 = -4/pi^2 (piecewise linear).
     */
    double getFirstFourierCoefficient() const;

private:
    Shape shape;
};

} // namespace OpenMMDPD

#endif

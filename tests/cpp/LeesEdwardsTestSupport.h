#ifndef OPENMMDPD_LEESEDWARDSTESTSUPPORT_H_
#define OPENMMDPD_LEESEDWARDSTESTSUPPORT_H_

// What the Lees-Edwards tests of the host and GPU platforms share: the sheared fluid's momentum zeroed
// and its streaming profile measured.

#include "DPDTestSupport.h"

namespace OpenMMDPDTest {

/** Remove the mean velocity, so that the total (peculiar) momentum is zero to round-off. */
inline void zeroMomentum(OpenMM::Context& context) {
    std::vector<OpenMM::Vec3> velocities = context.getState(OpenMM::State::Velocities).getVelocities();
    OpenMM::Vec3 mean;
    for (const OpenMM::Vec3& v : velocities)
        mean += v/static_cast<double>(velocities.size());
    for (OpenMM::Vec3& v : velocities)
        v -= mean;
    context.setVelocities(velocities);
}

/** The streaming profile <v_x>(y) in the lab frame (v + kappa y e_x) over equal bins of y, and the fit of its slope. */
struct StreamingProfile {
    std::vector<BlockEstimate> bins;
    BlockEstimate slope;
    BlockEstimate kineticTemperature, configurationalTemperature; // in units of the target kT
};

inline StreamingProfile measureProfile(OpenMM::Context& context, OpenMMDPD::DPDIntegrator& integrator, double kappa, int numBins,
                                       int numSamples, int stepsPerSample) {
    StreamingProfile profile;
    std::vector<std::vector<double> > binSeries(numBins);
    std::vector<double> slopeSeries, kinetic, gradientSquared, laplacian;
    for (int sample = 0; sample < numSamples; sample++) {
        integrator.step(stepsPerSample);
        kinetic.push_back(OpenMMDPD::DPDObservables::kineticTemperature(context)/reducedTemperature); // peculiar velocities
        if (sample%4 == 0) {
            OpenMMDPD::DPDObservables::ConfigurationalSums sums = OpenMMDPD::DPDObservables::configurationalSums(context);
            gradientSquared.push_back(sums.gradientSquared);
            laplacian.push_back(sums.laplacian); // kT = 1 kJ/mol: <|grad U|^2>/<lap U> is T_conf/T
        }
        OpenMM::State state = context.getState(OpenMM::State::Positions | OpenMM::State::Velocities);
        OpenMM::Vec3 a, b, c;
        state.getPeriodicBoxVectors(a, b, c);
        double L = b[1];
        std::vector<double> sum(numBins, 0.0), count(numBins, 0.0);
        double sxy = 0.0, syy = 0.0, sx = 0.0, sy = 0.0, n = 0.0;
        for (std::size_t i = 0; i < state.getPositions().size(); i++) {
            double y = state.getPositions()[i][1];
            if (!(y >= 0.0 && y < L)) { // the sheared step wraps every particle into the primary cell (its bin)
                ADD_FAILURE() << "particle " << i << " at y = " << y << ", outside [0, " << L << ")";
                profile.bins.assign(numBins, BlockEstimate()); // so that the caller's checks index nothing out of range
                return profile;
            }
            double vx = state.getVelocities()[i][0] + kappa*y; // lab frame
            int bin = std::min(numBins-1, static_cast<int>(y/L*numBins));
            sum[bin] += vx;
            count[bin] += 1.0;
            sxy += y*vx; syy += y*y; sx += vx; sy += y; n += 1.0;
        }
        for (int k = 0; k < numBins; k++)
            binSeries[k].push_back(count[k] > 0 ? sum[k]/count[k] : 0.0);
        slopeSeries.push_back((sxy - sx*sy/n)/(syy - sy*sy/n)); // least-squares slope of v_x against y
    }
    for (const auto& series : binSeries)
        profile.bins.push_back(blockAverage(series));
    profile.slope = blockAverage(slopeSeries);
    profile.kineticTemperature = blockAverage(kinetic);
    profile.configurationalTemperature = blockRatio(gradientSquared, laplacian);
    return profile;
}

} // namespace OpenMMDPDTest

#endif

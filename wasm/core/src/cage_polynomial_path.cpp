#include "mrvol/cage_polynomial_path.h"

#include "mrvol/error.h"

namespace mrvol {

void CagePolynomialPath::set(CagePolynomial poly, double volumeNow) {
  std::vector<double> shifted;
  session_->shiftedCage(shifted);
  poly.constant = volumeNow - (poly.evaluate(shifted.data(), nullptr) - poly.constant);
  polynomial_ = std::make_unique<CagePolynomialVolume>(std::move(poly));
  polynomial_->polynomial().chooseSweepThreads(shifted.data());
  constraint_ = std::make_unique<CageVolumeConstraint>(*polynomial_, *session_);
  detailsMoved_ = false;
}

void CagePolynomialPath::useTensor(const VolumeTensor& tensor, double volumeNow) {
  builder_.reset();
  set(contractCageRows(tensor, session_->x.data()), volumeNow);
}

void CagePolynomialPath::useBuilder(std::unique_ptr<CagePolynomialBuilder> builder, double volumeNow) {
  set(builder->build(session_->x.data()), volumeNow);
  builder_ = std::move(builder);
}

void CagePolynomialPath::rebuild(double volumeNow) { set(builder_->build(session_->x.data()), volumeNow); }

void CagePolynomialPath::reset() {
  builder_.reset();
  polynomial_.reset();
  constraint_.reset();
  detailsMoved_ = false;
}

CageVolumeConstraint& CagePolynomialPath::constraint(double reference) {
  constraint_->referenceVolume = reference;
  return *constraint_;
}

double CagePolynomialPath::gradient(std::vector<double>& gradient) const {
  if (!polynomial_) throw Error("no tensor is in use");  // nor a built polynomial: the path is matrix-free
  std::vector<double> cage;
  session_->shiftedCage(cage);
  gradient.assign(cage.size(), 0.0);
  return polynomial_->value(cage.data(), gradient.data());
}

}  // namespace mrvol

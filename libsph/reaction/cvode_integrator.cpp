#include "libsph/reaction/cvode_integrator.hpp"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <stdexcept>
#include <string>

namespace sph {

struct CvodeIntegrator::Impl {
  std::size_t n;
  RightHandSide rhs;
  Settings settings;
  SUNContext context = nullptr;
  N_Vector state = nullptr;
  SUNMatrix matrix = nullptr;
  SUNLinearSolver linear_solver = nullptr;
  void* memory = nullptr;
  bool initialised = false;
  long steps_before_reset = 0;

  static int right_hand_side(sunrealtype t, N_Vector y, N_Vector dydt, void* user) {
    auto& self = *static_cast<Impl*>(user);
    self.rhs(t, std::span<const double>(N_VGetArrayPointer(y), self.n), std::span<double>(N_VGetArrayPointer(dydt), self.n));
    return 0;
  }

  void check(int flag, const char* call) const {
    if (flag < 0) throw std::runtime_error(std::string("CVODE: ") + call + " failed: " + CVodeGetReturnFlagName(flag));
  }

  long current_steps() const {
    long s = 0;
    if (initialised) CVodeGetNumSteps(memory, &s);
    return s;
  }
};

CvodeIntegrator::CvodeIntegrator(std::size_t n_states, RightHandSide rhs, Settings settings)
    : impl_(std::make_unique<Impl>()) {
  impl_->n = n_states;
  impl_->rhs = std::move(rhs);
  impl_->settings = settings;
  if (SUNContext_Create(nullptr, &impl_->context) != 0) throw std::runtime_error("CVODE: cannot create a SUNDIALS context");
  impl_->state = N_VNew_Serial(static_cast<sunindextype>(n_states), impl_->context);
  impl_->matrix = SUNDenseMatrix(static_cast<sunindextype>(n_states), static_cast<sunindextype>(n_states), impl_->context);
  impl_->linear_solver = SUNLinSol_Dense(impl_->state, impl_->matrix, impl_->context);
  impl_->memory = CVodeCreate(CV_BDF, impl_->context);
  if (!impl_->state || !impl_->matrix || !impl_->linear_solver || !impl_->memory)
    throw std::runtime_error("CVODE: out of memory creating the solver");
}

CvodeIntegrator::~CvodeIntegrator() {
  CVodeFree(&impl_->memory);
  SUNLinSolFree(impl_->linear_solver);
  SUNMatDestroy(impl_->matrix);
  N_VDestroy(impl_->state);
  SUNContext_Free(&impl_->context);
}

void CvodeIntegrator::reset(double t, std::span<const double> y) {
  double* data = N_VGetArrayPointer(impl_->state);
  for (std::size_t k = 0; k < impl_->n; ++k) data[k] = y[k];
  if (!impl_->initialised) {
    impl_->check(CVodeInit(impl_->memory, &Impl::right_hand_side, t, impl_->state), "CVodeInit");
    impl_->check(CVodeSetUserData(impl_->memory, impl_.get()), "CVodeSetUserData");
    impl_->check(CVodeSetLinearSolver(impl_->memory, impl_->linear_solver, impl_->matrix), "CVodeSetLinearSolver");
    impl_->check(CVodeSStolerances(impl_->memory, impl_->settings.relative_tolerance, impl_->settings.absolute_tolerance),
                 "CVodeSStolerances");
    impl_->check(CVodeSetMaxNumSteps(impl_->memory, impl_->settings.max_steps), "CVodeSetMaxNumSteps");
    if (impl_->settings.max_step > 0) impl_->check(CVodeSetMaxStep(impl_->memory, impl_->settings.max_step), "CVodeSetMaxStep");
    impl_->initialised = true;
  } else {
    impl_->steps_before_reset += impl_->current_steps();
    impl_->check(CVodeReInit(impl_->memory, t, impl_->state), "CVodeReInit");
  }
}

void CvodeIntegrator::advance_to(double t_out, std::span<double> y) {
  if (!impl_->initialised) throw std::logic_error("CVODE: advance_to before reset");
  sunrealtype t_reached = 0;
  impl_->check(CVodeSetStopTime(impl_->memory, t_out), "CVodeSetStopTime");
  impl_->check(CVode(impl_->memory, t_out, impl_->state, &t_reached, CV_NORMAL), "CVode");
  const double* data = N_VGetArrayPointer(impl_->state);
  for (std::size_t k = 0; k < impl_->n; ++k) y[k] = data[k];
}

long CvodeIntegrator::steps() const { return impl_->steps_before_reset + impl_->current_steps(); }

}  // namespace sph

#pragma once
// The cell models a scene can choose by name, as one variant: the choice is resolved once per
// particle loop (std::visit outside the loop), never per particle.

#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>

#include "libsph/reaction/aliev_panfilov.hpp"
#include "libsph/reaction/fitzhugh_nagumo.hpp"
#include "libsph/reaction/ten_tusscher_panfilov_2006.hpp"

namespace sph {

using AnyCellModel = std::variant<FitzHughNagumo, AlievPanfilov, TenTusscherPanfilov2006>;

/// Names accepted by make_cell_model, in the order of the variant.
inline constexpr std::array<std::string_view, 3> cell_model_names{"fitzhugh_nagumo", "aliev_panfilov",
                                                                  "ten_tusscher_panfilov_2006"};

/// The model named `name` with its default (published) parameters, in ms and mV.
inline AnyCellModel make_cell_model(std::string_view name) {
  if (name == cell_model_names[0]) return FitzHughNagumo{};
  if (name == cell_model_names[1]) return AlievPanfilov{};
  if (name == cell_model_names[2]) return TenTusscherPanfilov2006{};
  throw std::invalid_argument("unknown cell model '" + std::string(name) +
                              "' (expected fitzhugh_nagumo, aliev_panfilov or ten_tusscher_panfilov_2006)");
}

inline std::string_view name_of(const AnyCellModel& model) { return cell_model_names[model.index()]; }

}  // namespace sph

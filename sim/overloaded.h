// A visitor from lambdas for std::visit over a closed set of alternatives
// (the force generators, the collider shapes):
//   std::visit(Overloaded{[](const A&) {...}, [](const B&) {...}}, v);
#pragma once

namespace sim {

template <class... Ts>
struct Overloaded : Ts... {
    using Ts::operator()...;
};
// (A deduction guide: GCC does without, clang before 17 does not.)
template <class... Ts>
Overloaded(Ts...) -> Overloaded<Ts...>;

}  // namespace sim

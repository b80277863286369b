#include "contact/elimination/elimination_impl.hpp"

namespace conserve::contact {

template class Elimination<2>;

}  // namespace conserve::contact

#include "contact/elimination/elimination_impl.hpp"

namespace conserve::contact {

template class Elimination<3>;

}  // namespace conserve::contact

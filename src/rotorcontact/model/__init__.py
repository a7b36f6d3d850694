"""The model: parameters and units, the exact free flight, the impact law and the contact laws
(docs/MODEL.md §1-§4). Every formula of the model lives here, once; the layers above call it."""

//! Pictures for trigbody.

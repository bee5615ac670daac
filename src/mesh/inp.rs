//! CalculiX/Abaqus deck (`.inp`) reader and writer.

"""The file formats: bearing, profile and sweep TOML files, units, shipped files.

The schema of every input field is :data:`pipeline.schema.fields.FIELDS`.
"""
from .config import (apply_override, bearing_from_dict, load_bearing, load_profile, lookup,
                     parse_set, parse_sets, parse_value, profile_from_dict, read_toml, resolve_path)
from .fields import FIELDS, REQUIRED, Field, check_set_key
from .parameters import ParameterRow, parameter_table
from .sweepfile import (MODEL_VERSION, OPERATING_POINT, REALIZATION, CaseSpec, Sweep, read_sweep_file,
                        sweep_from_dict)
from .units import (SI_UNITS, compose_units, format_quantity, parse_quantity, registry, si_udunits,
                    udunits)
from .stored import StoredConfiguration, stored_configuration

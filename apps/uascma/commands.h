#pragma once
// Each `uascma <command>` lives in its own file and adds itself to the application here.
// A command's callback throws uascma::InputError for bad input; main() turns it into exit code 2.
#include <CLI/CLI.hpp>

namespace uascma::cli {

void AddPolicyCommand(CLI::App& app);     // policy_command.cc
void AddSimulateCommand(CLI::App& app);   // simulate_command.cc
void AddPlotCommand(CLI::App& app);       // plot_command.cc
void AddRulCommand(CLI::App& app);        // rul_command.cc
void AddThrustCommand(CLI::App& app);     // thrust_command.cc
void AddAuthorityCommand(CLI::App& app);  // authority_command.cc
void AddEodCommand(CLI::App& app);        // eod_command.cc
void AddFootprintCommand(CLI::App& app);  // footprint_command.cc
void AddCampaignCommand(CLI::App& app);   // campaign_command.cc
void AddReportCommand(CLI::App& app);     // report_command.cc
void AddMapCommand(CLI::App& app);        // map_command.cc
void AddBatteryCommand(CLI::App& app);    // battery_command.cc
void AddBatteryHindsight(CLI::App* battery);  // battery_hindsight_command.cc (under `battery`)
void AddLearnCommand(CLI::App& app);      // learn_command.cc, learn_transitions_command.cc
void AddStoreCommand(CLI::App& app);      // store_command.cc
void AddReproduceCommand(CLI::App& app);  // reproduce_command.cc
void AddDocsCommand(CLI::App& app);       // docs_command.cc
void AddCalibrateCommand(CLI::App& app);  // calibrate_command.cc
void AddSitlCommand(CLI::App& app);       // sitl_command.cc
void AddCompanionCommand(CLI::App& app);  // companion_command.cc
void AddIdentifyCommand(CLI::App& app);   // identify_command.cc
void AddValidateCommand(CLI::App& app);   // validate_command.cc

}  // namespace uascma::cli

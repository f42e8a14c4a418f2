"""gearsim.signals"""
